// SPDX-License-Identifier: MIT
// Tests of the TOML scene reader: what toml++ must not see (deep dotted keys, non-ASCII
// outside strings) and the command line's --set overrides.
#include "scene_io_test_util.hpp"
#include "tumble/pipeline.hpp"

using namespace scene_io_test;

// toml++ 3.3.0 parses a dotted key by recursion and overflowed the stack (SIGSEGV) on a key or
// header of 40 000 parts: refused before it parses, with the line; 63 parts still reach it (and
// its own message), and dots in values, strings and comments do not count.
TEST(SceneIo, DeepDottedKeysAreRefusedBeforeTomlParsesThem) {
  std::string deep;
  for (int k = 0; k < 40000; ++k) deep += "x.";
  // (Strings built by +=: GCC 12 warns falsely, -Wrestrict, on some chains of +.)
  std::string key = deep, header = "z = 1\n[";
  key += "y = 1\n";
  header += deep;
  header += "y]\n";
  expectError(withExtra(key), 12, {"dotted key or table header of more than 64 parts"});
  expectError(withExtra(header), 13, {"more than 64 parts"});
  // Below the bound, in comments and strings, and in values: toml++ and the reader decide (here
  // an unknown key of [[body]]), not the bound.
  std::string parts63, dotty = "# ";
  for (int k = 0; k < 63; ++k) parts63 += "x.";
  parts63 += "y = 1\n";
  dotty += deep;
  dotty += "\nnote = \"";
  dotty += deep;
  dotty += "\"\n";
  for (int k = 0; k < 100; ++k) {
    dotty += 'v';
    dotty += std::to_string(k);
    dotty += " = [1.5, 2.5, 3.5]\n";
  }
  for (const std::string& extra : {parts63, dotty}) {
    try {
      (void)tumble::parseScene(withExtra(extra), "test.toml");
      ADD_FAILURE() << "an unknown key was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("parts"), std::string::npos) << e.what();
    }
  }
}

// A [[fill]] region of radius 1e28 m (found by the scene fuzzer): the placement's cell indices
// went beyond 2^63 (undefined, UBSan in the sanitizer build); they are clamped, and the fill
// places its bodies.
TEST(SceneIo, AFillRegionBeyondTheCellIndexRangePlacesItsBodies) {
  const std::string text = join({"[scene]", "dt = 1e-4", "steps = 1", "seed = 3", "[[shape]]", "name = \"small\"",
                                 "[[shape.sphere]]", "radius = 0.01", "mass = 0.01", "[[fill]]", "shapes = [\"small\"]",
                                 "count = 87", "region = \"cylinder\"", "point = [0, 0, 0]", "axis = [0, 0, 0.5]",
                                 "radius = 1e18"});
  // (The finding's radius, 1e28 m, is now refused: beyond ±2^60 m, issue 34 item 7. 1e18 m in
  // cells of 0.04 m still gives indices beyond 2^62.)
  const tumble::Scene s = tumble::parseScene(text, "test.toml");
  ASSERT_EQ(s.bodies.size(), 87u);
  for (const tumble::BodyDef& b : s.bodies) EXPECT_TRUE(std::isfinite(b.position.x) && std::isfinite(b.position.y));
  std::string beyond = text;
  beyond.replace(beyond.find("radius = 1e18"), 13, "radius = 9999999999999999999999999990.1");
  EXPECT_THROW((void)tumble::parseScene(beyond, "test.toml"), tumble::InputError);
}

// toml++ 3.3.0 has undefined behaviour for some non-ASCII code points where it expects
// whitespace ("Ñ", found by UBSan): they are refused, with the line, before it parses; in
// strings (all four kinds) and comments they are fine.
TEST(SceneIo, NonAsciiOutsideStringsIsRefusedWithTheLine) {
  expectError(withExtra("# note\nfoo =\xc3\x91 1\n"), 13, {"non-ASCII character outside a string or comment"});
  expectError(withExtra("x = '''a\n\xc3\x91'''\ny = 1 \xc3\x91\n"), 14, {"non-ASCII"});
  const std::string ok = withExtra("# comentario: a\xc3\xb1o\n");
  EXPECT_NO_THROW((void)tumble::parseScene(ok, "test.toml"));
  std::vector<std::string> ls = baseLines();
  ls.at(4) = "name = \"\xc3\xb1" "and\xc3\xba \\\" \xc3\x91\"";   // the shape's name, with an escaped quote
  ls.at(9) = "shape = '\xc3\xb1" "and\xc3\xba \" \xc3\x91'";        // a literal string naming it
  EXPECT_EQ(tumble::parseScene(join(ls), "test.toml").shapes.at(0).name, "\xc3\xb1" "and\xc3\xba \" \xc3\x91");
}

TEST(SceneIo, AsciiCheckFollowsTomlStrings) {
  // A byte-order mark is skipped (as toml++ does).
  EXPECT_NO_THROW((void)tumble::parseScene("\xEF\xBB\xBF" + join(baseLines()), "test.toml"));
  // A multi-line string may end in one or two quotes before its closing three: the scan must not
  // close it early and take the rest of the line for string content.
  expectError(withExtra("x = \"\"\"a\"\"\"\" \xc3\x91\n"), 12, {"non-ASCII"});
  // A line-ending backslash in a multi-line basic string still counts its line.
  expectError(withExtra("x = \"\"\"a \\\nb\"\"\"\ny = \xc3\x91\n"), 14, {"non-ASCII"});
}

// ---------------------------------------------------------------------------------------
// --set overrides (docs/scenes.md, "Overriding keys on the command line").

TEST(SceneOverrides, ChangeTheParsedValues) {
  const std::string file = withExtra("[ground]\nfriction = 0.9\n[output]\nrecord = \"a.bin\"\n");
  const Scene s = withSets(file, {"ground.friction=0.3", "scene.gravity=[0, 0, -9.8]", "output.record=\"x.bin\"",
                                  "output.debug=true", "integrator.rotation='splitting'", " scene.steps = 20"});
  EXPECT_EQ(s.ground.friction, 0.3f);
  EXPECT_EQ(s.gravity.x, 0.0f);
  EXPECT_EQ(s.gravity.z, -9.8f);
  EXPECT_EQ(s.recordFile, "x.bin");
  EXPECT_TRUE(s.recordDebug);
  EXPECT_EQ(s.integrator.rotation, tumble::RotationScheme::Splitting);
  EXPECT_EQ(s.steps, 20u);
  EXPECT_TRUE(s.ground.enabled);
  EXPECT_EQ(s.dt, 1e-4f) << "keys not set keep the file's values";
  // Tables the file lacks are added ([ground]'s presence turns the ground on, as in a file).
  const Scene t = withSets(join(baseLines()), {"contact.damping=2", "pulls.on=[\"x\"]", "ground.height=-1"});
  EXPECT_EQ(t.contact.damping, 2.0f);
  EXPECT_EQ(t.contact.stiffness, 2.0e4f);
  EXPECT_EQ(t.pulls.active, static_cast<std::uint32_t>(tumble::kPullX));
  EXPECT_TRUE(t.ground.enabled);
  EXPECT_EQ(t.ground.height, -1.0f);
  // The last of a key wins; an integer is a number, as in a file.
  EXPECT_EQ(withSets(file, {"ground.friction=0.3", "ground.friction=1"}).ground.friction, 1.0f);
  EXPECT_EQ(withSets(file, {"ground.enabled=false"}).ground.enabled, false);
}

TEST(SceneOverrides, SameSceneAsTheFileEditedTheSameWay) {
  const std::string group = "[[group]]\nshape = \"ball\"\ncount = [3, 3, 2]\nspacing = 2\njitter = 0.3\n"
                            "random_orientation = true\n";
  const Scene set = withSets(withExtra(group), {"scene.seed=7"});
  std::vector<std::string> ls = baseLines();
  ls.insert(ls.begin() + 1, "seed = 7");
  const Scene file = tumble::parseScene(join(ls) + group, "test.toml");
  EXPECT_TRUE(sameBits(set, file));
  EXPECT_FALSE(sameBits(set, tumble::parseScene(withExtra(group), "test.toml"))) << "the seed changes the groups";
  // No overrides: the scene of the file alone.
  EXPECT_TRUE(sameBits(tumble::readSceneFile(scenePath("molecules.toml"), {}),
                       tumble::readSceneFile(scenePath("molecules.toml"))));
}

TEST(SceneOverrides, ErrorsNameTheOriginAndNoLine) {
  const std::string base = join(baseLines());
  expectSetError(base, {"ground.friction=-1"}, "ground.friction=-1", {"[ground]: friction must be >= 0 (got -1)"});
  expectSetError(base, {"ground.frictoin=0.3"}, "ground.frictoin=0.3",
                 {"[ground]: unknown key 'frictoin'; allowed keys: enabled, height, stiffness, friction"});
  expectSetError(base, {"scene.steps=1.5"}, "scene.steps=1.5", {"[scene]: steps must be an integer (got 1.5)"});
  expectSetError(base, {"scene.gravity=[0, 0]"}, "scene.gravity=[0, 0]", {"gravity must be an array of 3 numbers"});
  expectSetError(base, {"pulls.on=[\"z\"]"}, "pulls.on=[\"z\"]", {"unknown pull \"z\""});
  // A table made by --set: its problems name the override that made it.
  std::vector<std::string> noScene = baseLines();
  noScene.erase(noScene.begin(), noScene.begin() + 3);
  expectSetError(join(noScene), {"scene.dt=1e-3"}, "scene.dt=1e-3", {"[scene]: missing required key 'steps'"});
  // The override that is wrong is named, not the first one.
  expectSetError(base, {"ground.friction=0.3", "contact.shear=-2"}, "contact.shear=-2", {"shear must be >= 0"});
}

// Entries of arrays of tables (issue 35, item 7): ARRAY[INDEX].KEY (INDEX from 0) or
// ARRAY.NAME.KEY (the entry whose `name` is NAME), nested arrays too.
const std::string kTwoWalls = "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\nfriction = 0.5\n"
                              "[[wall]]\ntype = \"plane\"\npoint = [0, 0, 5]\nnormal = [0, 0, -1]\n";

TEST(SceneOverrides, EntriesOfArraysByIndexAndName) {
  const Scene s = withSets(withExtra(kTwoWalls), {"wall[1].friction=0.1", "wall[0].point=[0, 0, -1]",
                                                  "shape.ball.sphere[0].radius=0.25", "shape[0].sphere[0].mass=2",
                                                  "body[0].position=[0, 0, 2]"});
  ASSERT_EQ(s.walls.size(), 2u);
  EXPECT_EQ(s.walls[1].contact.friction, 0.1f);
  EXPECT_EQ(s.walls[0].contact.friction, 0.5f) << "the other entry keeps the file's values";
  EXPECT_EQ(s.walls[0].point.z, -1.0f);
  EXPECT_EQ(s.shapes.at(0).spheres.at(0).radius, 0.25f);
  EXPECT_EQ(s.shapes[0].spheres[0].mass, 2.0f);
  EXPECT_EQ(s.bodies.at(0).position.z, 2.0f);
  // The same scene as the file edited the same way (a group's lattice too).
  const std::string group = "[[group]]\nshape = \"ball\"\ncount = [3, 3, 2]\nspacing = 2\njitter = 0.3\n"
                            "random_orientation = true\n";
  std::vector<std::string> ls = baseLines();
  ls.at(6) = "radius = 0.25";
  const std::string edited = join(ls) + "[[group]]\nshape = \"ball\"\ncount = [2, 2, 2]\nspacing = 2\njitter = 0.3\n"
                                        "random_orientation = true\n";
  const Scene set = withSets(withExtra(group), {"group[0].count=[2, 2, 2]", "shape.ball.sphere[0].radius=0.25"});
  EXPECT_EQ(set.bodies.size(), 9u);
  EXPECT_TRUE(sameBits(set, tumble::parseScene(edited, "test.toml")));
  // [[material]] by name; a renamed entry is found by its new name; the last of a key wins.
  const std::string mats = withLine(8, "material = \"glass\"") + kHertz + kGlass + kSteel;
  const Scene m = withSets(mats, {"material.steel.friction=0.7", "material[0].restitution=0.5"});
  EXPECT_EQ(m.materials.at(1).friction, 0.7f);
  EXPECT_EQ(m.materials[0].restitution, 0.5f);
  EXPECT_EQ(m.materials[0].friction, 0.3f);
  const Scene r = withSets(mats, {"material.steel.name=\"iron\"", "material.iron.friction=0.2", "material.iron.friction=0.4"});
  EXPECT_EQ(r.materials.at(1).name, "iron");
  EXPECT_EQ(r.materials[1].friction, 0.4f);
}

TEST(SceneOverrides, EntriesAreCheckedAsTheFileIs) {
  const std::string walls = withExtra(kTwoWalls);
  expectSetError(walls, {"wall[0].friction=-1"}, "wall[0].friction=-1", {"[[wall]] #1: friction must be >= 0 (got -1)"});
  expectSetError(walls, {"wall[1].frictoin=0.1"}, "wall[1].frictoin=0.1", {"[[wall]] #2: unknown key 'frictoin'"});
  expectSetError(walls, {"wall[1].radius=1"}, "wall[1].radius=1", {"radius is not a key of type = \"plane\""});
  expectSetError(join(baseLines()), {"shape.ball.sphere[0].radius=0"}, "shape.ball.sphere[0].radius=0",
                 {"shape \"ball\", [[shape.sphere]] #1: radius must be > 0 (got 0)"});
  const std::string mats = withLine(8, "material = \"glass\"") + kHertz + kGlass + kSteel;
  expectSetError(mats, {"material.glass.poisson_ratio=0.5"}, "material.glass.poisson_ratio=0.5",
                 {"[[material]] #1: poisson_ratio must be in [0, 0.5) (got 0.5)"});
  // Entries the file lacks: named with the entries there are.
  expectSetError(walls, {"wall[2].friction=0.1"}, "wall[2].friction=0.1",
                 {"wall[2]: the scene has 2 [[wall]] tables, wall[0] and wall[1]"});
  expectSetError(walls + kTwoWalls, {"wall[4].friction=0.1"}, "wall[4].friction=0.1",
                 {"wall[4]: the scene has 4 [[wall]] tables, wall[0] to wall[3]"});
  expectSetError(join(baseLines()), {"wall[0].friction=0.1"}, "wall[0].friction=0.1",
                 {"wall: the scene has no [[wall]] tables"});
  expectSetError(join(baseLines()), {"shape.ball.sphere[1].radius=1"}, "shape.ball.sphere[1].radius=1",
                 {"shape.ball.sphere[1]: shape.ball has 1 [[shape.sphere]] table, shape.ball.sphere[0]"});
  expectSetError(mats, {"material.glas.friction=0.1"}, "material.glas.friction=0.1",
                 {"material.glas: no [[material]] is named \"glas\"; the names: \"glass\" (material[0]), "
                  "\"steel\" (material[1])"});
  expectSetError(walls, {"wall.left.friction=0.1"}, "wall.left.friction=0.1",
                 {"wall.left: [[wall]] tables have no name; pick one by its index: the scene has 2 [[wall]] tables, "
                  "wall[0] and wall[1]"});
  expectSetError(walls, {"wall[0].point.x=1"}, "wall[0].point.x=1",
                 {"wall[0].point is not an array of tables (it is an array): the path ends at the key"});
  expectSetError(mats, {"material.glass=1"}, "material.glass=1", {"material is an array of tables, [[material]]: pick an entry by its index or its name"});
  expectSetError(join(baseLines()), {"shape.name=\"x\""}, "shape.name=\"x\"",
                 {"shape[INDEX].KEY=VALUE (INDEX from 0) or shape.NAME.KEY=VALUE"});
  expectSetError(join(baseLines()), {"shape.ball.sphere.radius=1"}, "shape.ball.sphere.radius=1",
                 {"shape.ball.sphere is an array of tables, [[shape.sphere]]: pick an entry by its index or its name"});
  expectSetError(join(baseLines()), {"ground[0].friction=1"}, "ground[0].friction=1", {"[ground] is one table"});
  expectSetError(walls, {"wall[0].normal[2]=1"}, "wall[0].normal[2]=1",
                 {"normal[2]: the last part is the key, and --set sets its whole value: write normal=VALUE"});
  expectSetError(walls, {"ground.friction[0]=1"}, "ground.friction[0]=1", {"friction[0]: the last part is the key"});
  // A file whose 'wall' is not an array of tables: the file's own error, at its line.
  try {
    (void)withSets("wall = 3\n" + join(baseLines()), {"wall[0].friction=0.3"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.toml");
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("'wall' must be an array of tables"), std::string::npos) << e.what();
  }
}

// The Python module's overrides (set=) name themselves as such, with Python examples.
TEST(SceneOverrides, PythonOverridesSaySet) {
  const std::string base = join(baseLines());
  const auto python = [&](const std::string& spec) -> std::string {
    try {
      (void)tumble::parseScene(base, "test.toml", {spec}, tumble::OverrideSource::Python);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "set=['" + spec + "']") << "(specs without quotes or backslashes)";
      EXPECT_EQ(e.line(), 0);
      return e.what();
    }
    ADD_FAILURE() << "no error for set=['" << spec << "']";
    return {};
  };
  EXPECT_EQ(python("ground.friction=-1"), "set=['ground.friction=-1']: [ground]: friction must be >= 0 (got -1)");
  const std::string malformed = python("foo");
  EXPECT_NE(malformed.find("e.g. set=['ground.friction=0.3']"), std::string::npos) << malformed;
  EXPECT_NE(malformed.find("set=['wall[0].friction=0.1'] or set=['material.glass.friction=0.3']"), std::string::npos)
      << malformed;
  EXPECT_EQ(malformed.find("--set"), std::string::npos) << malformed;
  EXPECT_NE(python("output.record=x").find("a string needs quotes, e.g. set=['output.record=\"run.bin\"']"),
            std::string::npos);
  EXPECT_NE(python("grund.x=1").find("set= can change the keys of"), std::string::npos);
  EXPECT_NE(python("wall[0].friction=1").find("wall: the scene has no [[wall]] tables"), std::string::npos);
  // Quoted as Python's repr() quotes: in double quotes when single ones are in it, the quote and
  // backslashes escaped.
  const auto origin = [&](const std::string& spec) -> std::string {
    try {
      (void)tumble::parseScene(base, "test.toml", {spec}, tumble::OverrideSource::Python);
    } catch (const InputError& e) {
      return e.file();
    }
    return "no error";
  };
  EXPECT_EQ(origin("scene.nam='a\\'"), "set=[\"scene.nam='a\\\\'\"]");
  EXPECT_EQ(origin("scene.nam=\"'\""), "set=['scene.nam=\"\\'\"']");
  EXPECT_EQ(origin("scene.name='x"), "set=[\"scene.name='x\"]");
}

TEST(SceneOverrides, UnknownTablesAreRefused) {
  const std::string base = join(baseLines());
  expectSetError(base, {"grund.friction=1"}, "grund.friction=1",
                 {"unknown section 'grund'", "--set can change the keys of [scene], [contact], [ground], [pulls], "
                  "[broadphase], [integrator], [output]", "and of the entries of [[material]], [[wall]], [[shape]]"});
  expectSetError(base, {"a.b.c=1"}, "a.b.c=1", {"unknown section 'a'"});
}

TEST(SceneOverrides, MalformedOrNotTomlIsRefused) {
  const std::string base = join(baseLines());
  for (const char* spec : {"foo", "=1", "ground.a.b=1", "ground=1", "ground.=1", ".friction=1", "ground.friction",
                           "ground.\"friction\"=1", "ground.fri ction=1", "wall[0]=1", "wall[].friction=1",
                           "wall[-1].friction=1", "wall[0.friction=1", "wall[0]x.friction=1", "wall[1][2].friction=1",
                           "wall[99999999999999999999].friction=1"}) {
    expectSetError(base, {spec}, spec,
                   {"expected SECTION.KEY=VALUE", "--set ground.friction=0.3", "ARRAY[INDEX].KEY=VALUE (INDEX from 0)",
                    "ARRAY.NAME.KEY=VALUE, e.g. --set 'wall[0].friction=0.1' or --set material.glass.friction=0.3"});
  }
  expectSetError(base, {"output.record=x.bin"}, "output.record=x.bin",
                 {"TOML syntax error", "a string needs quotes, e.g. --set output.record='\"run.bin\"'"});
  expectSetError(base, {"ground.friction="}, "ground.friction=", {"TOML syntax error", "a string needs quotes"});
  try {
    (void)withSets(base, {"scene.gravity=[0, 0"});
    ADD_FAILURE() << "no error for an unclosed array";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set scene.gravity=[0, 0");
    EXPECT_NE(std::string(e.what()).find("TOML syntax error"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("needs quotes"), std::string::npos) << "not a bare word: " << e.what();
  }
  expectSetError(base, {"ground.friction=1\nheight = 2"}, "ground.friction=1\nheight = 2",
                 {"VALUE must be one TOML value"});
  expectSetError(base, {"ground.friction=1\n[scene]"}, "ground.friction=1\n[scene]", {"VALUE must be one TOML value"});
  // Non-ASCII outside a string is refused as in a file; in a string it is fine.
  expectSetError(base, {"scene.name=\xc3\x91"}, "scene.name=\xc3\x91", {"non-ASCII character outside a string"});
  EXPECT_EQ(withSets(base, {"scene.name=\"a\xc3\xb1o\""}).name, "a\xc3\xb1o");
}

TEST(SceneOverrides, FileErrorsStayTheFiles) {
  // A problem in the file is reported at its line, overrides or not.
  expectError(withLine(7, "radius = -1"), 7, {"radius must be > 0"});
  try {
    (void)withSets(withLine(7, "radius = -1"), {"ground.friction=0.3"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.toml");
    EXPECT_EQ(e.line(), 7);
  }
  try {
    (void)withSets("ground = 3\n" + join(baseLines()), {"ground.friction=0.3"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.toml");
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(std::string(e.what()).find("'ground' must be a table"), std::string::npos) << e.what();
  }
  // A malformed override is reported before the file is read (here: a missing file).
  try {
    (void)tumble::readSceneFile("/nonexistent/scene.toml", {"foo"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "command line, --set foo");
  }
}

// A NUL byte in user text (a TOML key or string, Python's name= or set=) is shown as \0: what()
// is read as a C string, and a raw NUL cut the message short there (issue 34, item 12).
TEST(SceneMessages, ANulByteIsShownEscaped) {
  const auto what = [](const std::string& text, const std::string& name, const std::vector<std::string>& sets,
                       tumble::OverrideSource source) -> std::string {
    try {
      (void)tumble::parseScene(text, name, sets, source);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "no error";
    return {};
  };
  const std::string base = join(baseLines());
  const std::string key = what(base + "[[wall]]\n\"ty\\u0000pe\" = \"plane\"\n", "test.toml", {},
                               tumble::OverrideSource::CommandLine);
  EXPECT_NE(key.find("unknown key 'ty\\0pe'; allowed keys:"), std::string::npos) << key;
  const std::string type = what(base + "[[wall]]\ntype = \"pl\\u0000ane\"\n", "test.toml", {},
                                tumble::OverrideSource::CommandLine);
  EXPECT_NE(type.find("unknown wall type \"pl\\0ane\" (\"plane\""), std::string::npos) << type;
  const std::string name = what(base + "[ground]\nfriction = -1\n", std::string("sce\0ne", 6), {},
                                tumble::OverrideSource::Python);
  EXPECT_EQ(name.rfind("sce\\0ne:13: [ground]: friction must be >= 0", 0), 0u) << name;
  const std::string set = what(base, "test.toml", {std::string("ground.friction=-1\0 # x", 23)},
                               tumble::OverrideSource::Python);
  EXPECT_NE(set.find("set=['ground.friction=-1\\0 # x']: "), std::string::npos) << set;
  EXPECT_EQ(set.find('\0'), std::string::npos);
  const std::string tab = what(base + "[ground]\nfriction = -1\n", "a\tb\x7f.toml", {}, tumble::OverrideSource::CommandLine);
  EXPECT_EQ(tab.rfind("a\\tb\\x7f.toml:13: ", 0), 0u) << tab;
}

// --set broadphase.skin=3e38: the detection grows every radius by half the skin, beyond single
// precision; refused at load naming the skin, where the sweep said "the particles are spread
// over…" of particles at the origin (issue 34, item 12).
TEST(SceneMessages, ASkinBeyondSinglePrecisionIsNamed) {
  const tumble::World w = tumble::World::fromScene(withSets(join(baseLines()), {"broadphase.skin=3e38"}));
  try {
    (void)tumble::effectiveSkin(w);
    ADD_FAILURE() << "no error";
  } catch (const tumble::Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("[broadphase] skin = 3e+38 m is beyond single precision's range for the contact detection", 0),
              0u) << what;
    EXPECT_NE(what.find("automatic: 0.25 m"), std::string::npos) << what;
  }
  EXPECT_EQ(tumble::effectiveSkin(tumble::World::fromScene(withSets(join(baseLines()), {"broadphase.skin=1e30"}))), 1e30f);
}
