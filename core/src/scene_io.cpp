// SPDX-License-Identifier: MIT
/// @file scene_io.cpp
/// TOML scene reader (schema: docs/scenes.md).
/// This file: the entry points, the TOML parse and its pre-check, the --set overrides (of the
/// single tables and of the entries of arrays of tables), and
/// SceneParser::run (the order the tables are read in). The tables are read by SceneParser's
/// members in scene_settings.cpp, scene_walls.cpp, scene_bodies.cpp and scene_fills.cpp;
/// TableReader and the shared helpers are in scene_reader.hpp/.cpp.
///
/// Design notes
/// - Every problem is reported as tumble::InputError(file, line, problem), where line is the
///   1-based line of the offending TOML node (toml++ keeps a source region for every key and
///   value), or 0 when the problem concerns the file as a whole (no [scene], no bodies).
///   Messages name the table, the key, the rule and the offending value, so that the user
///   knows what to change.
/// - Unknown keys are errors, not warnings: a misspelt key ("stifness") silently falling back
///   to a default is the commonest way to get a scene that runs but is not the one intended.
/// - Lattice groups are generated from tumble::Rng (SplitMix64), never <random>, and the
///   orientation uses tumble::sinCos (our own polynomial) rather than std::sin/std::cos, so a
///   scene file gives bit-identical bodies on every platform and standard library. Each group
///   has its own generator seeded from (scene seed, group index), and every body draws a fixed
///   number of values whatever its options, so editing one group never changes another.
/// - [[body]] and [[group]] are separate TOML arrays; bodies are emitted in file order by
///   sorting their tables by source position.
#include "tumble/scene_io.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "binary_io.hpp"
#include "scene_reader.hpp"
#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

namespace tumble::scene_reader {

Scene SceneParser::run() {
  Scene scene;
  scene.sourceFile = m_file;
  scene.name = stemOf(m_file);

  for (auto&& [key, value] : m_root) {
    (void)value;
    if (!isOneOf(kSingleTables, key.str()) && !isOneOf(kArrayTables, key.str())) {
      throw errorAt(m_file, sourceOf(key), "unknown top-level key '" + std::string(key.str()) +
                                               "'; allowed tables: " + tableNames(true));
    }
  }

  readScene(scene);
  readContact(scene);
  readMaterials(scene);
  readGround(scene);
  readPeriodic(scene);
  readWalls(scene);
  readPulls(scene);
  readBroadphase(scene);
  readIntegrator(scene);
  readOutput(scene);
  readShapes(scene);
  readBodies(scene);
  readFills(scene);
  readPours(scene);
  if (scene.bodies.empty() && scene.pourBodies.empty()) {
    throw InputError(m_file, 0, "the scene has no bodies; add a [[body]], a [[group]] or a [[fill]] "
                                "(and the [[shape]] it uses)");
  }
  checkPeriod(scene);
  checkWallResolution(scene);
  return scene;
}

}  // namespace tumble::scene_reader

namespace tumble {
namespace {

using scene_reader::arrayTableNames;
using scene_reader::isOneOf;
using scene_reader::kArrayTables;
using scene_reader::kSingleTables;
using scene_reader::SceneParser;
using scene_reader::sectionOf;
using scene_reader::tableNames;
using scene_reader::tablesOf;
using scene_reader::typeName;

// The most parts a dotted key or table header may have: tumble's deepest have two
// ("[[shape.sphere]]"); toml++ 3.3.0 parses a dotted key by recursion, one frame per part, and
// overflows the stack at some tens of thousands (an 80 KB file).
inline constexpr int kMaxKeyParts = 64;

// What toml++ must not see, refused before it parses, with the line: non-ASCII bytes outside
// strings and comments (its 3.3.0 reaches an "unreachable" branch, undefined behaviour, for some
// code points where it expects whitespace: U+00A1–U+0499, e.g. "Ñ"), and dotted keys of more
// than kMaxKeyParts parts (the dots outside strings and comments since the last newline, '=',
// ',', bracket or brace: a key's or a header's separators; a value such as 1.5 has one).
// Strings: "…" and '…', and their multi-line forms.
void checkBeforeToml(std::string_view t, const std::string& file) {
  long line = 1;
  int dots = 0;
  std::size_t i = t.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte-order mark (toml++ skips it)
  const auto starts = [&](std::string_view s) { return t.substr(i, s.size()) == s; };
  while (i < t.size()) {
    const char c = t[i];
    if (c == '\n' || c == '=' || c == ',' || c == '[' || c == ']' || c == '{' || c == '}') {
      dots = 0;
      if (c == '\n') ++line;
      ++i;
    } else if (c == '.') {
      if (++dots >= kMaxKeyParts)
        throw InputError(file, line,
                         "a dotted key or table header of more than " + std::to_string(kMaxKeyParts) +
                             " parts; tumble's keys have at most two (docs/scenes.md)");
      ++i;
    } else if (c == '#') {  // comment: to the end of the line
      while (i < t.size() && t[i] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool multi = starts(c == '"' ? "\"\"\"" : "'''");
      const std::size_t open = multi ? 3 : 1;
      i += open;
      for (;;) {
        if (i >= t.size()) return;  // unterminated: toml++ reports it
        if (t[i] == '\n') {
          if (!multi) break;  // toml++ reports the unterminated string
          ++line;
        }
        if (c == '"' && t[i] == '\\') {  // an escape in a basic string (a line-ending one too)
          if (i + 1 < t.size() && t[i + 1] == '\n') ++line;
          i += 2;
          continue;
        }
        if (t[i] == c && !multi) {
          ++i;
          break;
        }
        if (t[i] == c) {  // a run of quotes: three or more end the string, after the whole run
          std::size_t k = 0;
          while (i + k < t.size() && t[i + k] == c) ++k;
          i += k;
          if (k >= 3) break;
          continue;
        }
        ++i;
      }
    } else if (static_cast<unsigned char>(c) >= 0x80) {
      throw InputError(file, line,
                       "a non-ASCII character outside a string or comment; TOML allows them only in "
                       "\"strings\" and # comments");
    } else {
      ++i;
    }
  }
}

/// The TOML document of `text`, refused (InputError at `name` and the line) for a syntax error
/// or a non-ASCII character outside strings and comments.
toml::table parseToml(std::string_view text, const std::string& name) {
  checkBeforeToml(text, name);
#if TOML_EXCEPTIONS
  try {
    return toml::parse(text, std::string_view(name));
  } catch (const toml::parse_error& e) {
    throw InputError(name, static_cast<long>(e.source().begin.line),
                     "TOML syntax error: " + std::string(e.description()));
  }
#else
  toml::parse_result result = toml::parse(text, std::string_view(name));
  if (!result) {
    const toml::parse_error& e = result.error();
    throw InputError(name, static_cast<long>(e.source().begin.line),
                     "TOML syntax error: " + std::string(e.description()));
  }
  return std::move(result).table();
#endif
}

/// A Python string literal of `s`, as repr() writes it: in single quotes, or in double quotes
/// when it has single quotes and no double ones; backslashes and that quote escaped.
std::string pythonString(std::string_view s) {
  const char q = s.find('\'') != std::string_view::npos && s.find('"') == std::string_view::npos ? '"' : '\'';
  std::string out(1, q);
  for (const char c : s) {
    if (c == q || c == '\\') out += '\\';
    out += c;
  }
  return out + q;
}

/// How the overrides' messages name them: tumble's --set ("command line, --set SPEC") or the
/// Python module's set= ("set=['SPEC']"), and how their advice writes an example.
struct Naming {
  OverrideSource source;
  std::string origin(const std::string& spec) const {
    return source == OverrideSource::Python ? "set=[" + pythonString(spec) + "]" : "command line, --set " + spec;
  }
  /// An example override: `shell` as a shell passes it to --set, `spec` the override itself.
  std::string eg(std::string_view shell, std::string_view spec) const {
    return source == OverrideSource::Python ? "set=[" + pythonString(spec) + "]" : "--set " + std::string(shell);
  }
  std::string option() const { return source == OverrideSource::Python ? "set=" : "--set"; }
};

/// One part of an override's path: a key, with an index when it picks an entry of an array of
/// tables ("wall[1]").
struct PathPart {
  std::string key;
  std::optional<std::size_t> index;
};

/// A --set override, parsed: its path, and the document "[FIRST]\nKEY = VALUE" whose nodes have
/// the override's origin as their source path, so that the reader's messages name it.
struct Override {
  std::string origin;  // "command line, --set SPEC" or "set=['SPEC']" (Naming)
  std::vector<PathPart> path;  // SECTION KEY, or ARRAY[INDEX] ... KEY, or ARRAY NAME ... KEY
  toml::table doc;
  const std::string& section() const { return path.front().key; }
  const std::string& key() const { return path.back().key; }
};

/// A TOML bare key: letters, digits, '_' and '-'.
bool isBareKey(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string_view trimmed(std::string_view s) {
  const std::size_t b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

/// The parts of "a.b[2].c", or nothing when a part is not a bare key with at most one index of
/// digits.
std::optional<std::vector<PathPart>> splitPath(std::string_view name) {
  std::vector<PathPart> out;
  for (;;) {
    const std::size_t dot = name.find('.');
    std::string_view part = name.substr(0, dot);
    PathPart p;
    if (const std::size_t open = part.find('['); open != std::string_view::npos) {
      const std::string_view digits = part.substr(open + 1, part.size() - open - 2);
      std::size_t index = 0;
      const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
      if (part.back() != ']' || digits.empty() || ec != std::errc() || end != digits.data() + digits.size())
        return std::nullopt;
      p.index = index;
      part = part.substr(0, open);
    }
    if (!isBareKey(part)) return std::nullopt;
    p.key = std::string(part);
    out.push_back(std::move(p));
    if (dot == std::string_view::npos) return out;
    name = name.substr(dot + 1);
  }
}

/// The advice for a path that names an array of tables, `array` as the override writes it
/// ("shape.ball.sphere") and `header` its TOML header ("shape.sphere"), without an entry.
std::string pickAnEntry(const std::string& array, const std::string& header) {
  return array + " is an array of tables, [[" + header + "]]: pick an entry by its index or its name, " + array +
         "[INDEX].KEY=VALUE (INDEX from 0) or " + array + ".NAME.KEY=VALUE";
}

Override parseOverride(const std::string& spec, const Naming& naming) {
  Override o;
  o.origin = naming.origin(spec);
  const std::string_view text = spec;
  const std::size_t eq = text.find('=');
  std::optional<std::vector<PathPart>> path;
  if (eq != std::string_view::npos) path = splitPath(trimmed(text.substr(0, eq)));
  const bool single = path && isOneOf(kSingleTables, path->front().key);
  if (!path || path->size() < 2 || (single && path->size() != 2)) {
    throw InputError(o.origin, 0,
                     "expected SECTION.KEY=VALUE, one table and one of its keys (letters, digits, _ and -) and "
                     "a TOML value, e.g. " + naming.eg("ground.friction=0.3", "ground.friction=0.3") +
                         ", or for an entry of an array of tables ARRAY[INDEX].KEY=VALUE (INDEX from 0) or "
                         "ARRAY.NAME.KEY=VALUE, e.g. " + naming.eg("'wall[0].friction=0.1'", "wall[0].friction=0.1") +
                         " or " + naming.eg("material.glass.friction=0.3", "material.glass.friction=0.3"));
  }
  o.path = std::move(*path);
  if (!single && !isOneOf(kArrayTables, o.section())) {
    throw InputError(o.origin, 0,
                     "unknown section '" + o.section() + "'; " + naming.option() + " can change the keys of " +
                         tableNames(false) + ", and of the entries of " + arrayTableNames());
  }
  if (single && o.path.front().index) {
    throw InputError(o.origin, 0,
                     "[" + o.section() + "] is one table, not an array of tables: write " + o.section() + "." +
                         o.key() + " without an index");
  }
  if (o.path.back().index) {
    throw InputError(o.origin, 0,
                     o.key() + "[" + std::to_string(*o.path.back().index) + "]: the last part is the key, and " +
                         naming.option() + " sets its whole value: write " + o.key() +
                         "=VALUE (an array in full, e.g. [0, 0, 1])");
  }
  if (!single && !o.path.front().index && o.path.size() < 3)
    throw InputError(o.origin, 0, pickAnEntry(o.section(), o.section()));
  const std::string_view value = text.substr(eq + 1);
  try {
    o.doc = parseToml("[" + o.section() + "]\n" + o.key() + " = " + std::string(value) + "\n", o.origin);
  } catch (const InputError& e) {
    const std::string_view v = trimmed(value);
    const bool bare = v.empty() || std::string_view("\"'[{").find(v.front()) == std::string_view::npos;
    throw InputError(o.origin, 0,
                     e.problem() + (bare ? "; VALUE is TOML: a string needs quotes, e.g. " +
                                               naming.eg("output.record='\"run.bin\"'", "output.record=\"run.bin\"")
                                         : std::string()));
  }
  const toml::table* t = o.doc.get_as<toml::table>(o.section());
  if (o.doc.size() != 1 || t == nullptr || t->size() != 1) {
    throw InputError(o.origin, 0, "VALUE must be one TOML value, not more keys or tables");
  }
  return o;
}

std::vector<Override> parseOverrides(const std::vector<std::string>& specs, OverrideSource source) {
  const Naming naming{source};
  std::vector<Override> out;
  out.reserve(specs.size());
  for (const std::string& spec : specs) out.push_back(parseOverride(spec, naming));
  return out;
}

/// "wall[0] and wall[1]" or "wall[0] to wall[4]": the indices of the `n` entries of `array`.
std::string indicesOf(const std::string& array, std::size_t n) {
  const std::string last = array + "[" + std::to_string(n - 1) + "]";
  return n == 1 ? last : array + "[0]" + (n == 2 ? " and " : " to ") + last;
}

/// The entry of an array of tables that an override's path picks, by index or by name (an
/// entry's `name` key), nested arrays too ("shape.ball.sphere[0]"). An entry the file lacks is
/// refused naming the override and the entries there are; a top-level key of the file that is
/// not an array of tables gives the file's own error.
toml::table& entryOf(toml::table& root, const Override& o, const std::string& file) {
  toml::table* t = &root;
  std::string at;      // the path so far, as the override writes it ("shape.ball")
  std::string header;  // the array's TOML header: "wall", "shape.sphere"
  for (std::size_t i = 0; i + 1 < o.path.size(); ++i) {
    const PathPart& part = o.path[i];
    const std::string owner = at.empty() ? std::string("the scene") : at;
    const std::string array = at + (at.empty() ? "" : ".") + part.key;
    header += (header.empty() ? "" : ".") + part.key;
    const std::string none = owner + " has no [[" + header + "]] tables";
    toml::node* n = t->get(part.key);
    if (n == nullptr) throw InputError(o.origin, 0, array + ": " + none);
    if (!n->is_array() || (!n->as_array()->empty() && !n->is_array_of_tables())) {
      if (i == 0) (void)tablesOf(file, *n, "'" + part.key + "'", "[[" + header + "]]");  // the file's own error
      throw InputError(o.origin, 0,
                       array + " is not an array of tables (it is " + typeName(*n) + "): the path ends at the key "
                               "whose whole value is set");
    }
    toml::array& entries = *n->as_array();
    if (entries.empty()) throw InputError(o.origin, 0, array + ": " + none);
    const std::string count = owner + " has " + std::to_string(entries.size()) + " [[" + header + "]] table" +
                              (entries.size() == 1 ? "" : "s") + ", " + indicesOf(array, entries.size());
    std::size_t pick = 0;
    if (part.index) {
      pick = *part.index;
      at = array + "[" + std::to_string(pick) + "]";
      if (pick >= entries.size()) throw InputError(o.origin, 0, at + ": " + count);
    } else {
      if (i + 2 >= o.path.size() || o.path[i + 1].index) {
        throw InputError(o.origin, 0, pickAnEntry(array, header) + "; " + count);
      }
      const std::string& name = o.path[++i].key;
      at = array + "." + name;
      std::string names;
      pick = entries.size();
      for (std::size_t k = 0; k < entries.size(); ++k) {
        const toml::node* nn = entries.get(k)->as_table()->get("name");
        if (nn == nullptr || !nn->is_string()) continue;
        if (pick == entries.size() && nn->as_string()->get() == name) pick = k;
        names += (names.empty() ? "" : ", ") + ("\"" + nn->as_string()->get() + "\" (" + array + "[" +
                                                std::to_string(k) + "])");
      }
      if (pick == entries.size()) {
        throw InputError(o.origin, 0,
                         at + ": " + (names.empty() ? "[[" + header + "]] tables have no name; pick one by its "
                                                                          "index: " + count
                                                    : "no [[" + header + "]] is named \"" + name + "\"; the names: " +
                                                          names));
      }
    }
    t = entries.get(pick)->as_table();
  }
  return *t;
}

/// Puts the override's key into its table, replacing the file's value: moved, not copied, so
/// that the nodes keep their source. A single table the file lacks is added whole (its
/// problems then name the override); an entry of an array of tables must be in the file.
void applyOverride(toml::table& root, Override& o, const std::string& file) {
  toml::table& from = *o.doc.get_as<toml::table>(o.section());
  toml::table* to = nullptr;
  if (isOneOf(kSingleTables, o.section())) {
    if (root.get(o.section()) == nullptr) {
      root.insert(o.section(), std::move(from));
      return;
    }
    (void)sectionOf(file, root, o.section());  // the file's own error when it is not a table there
    to = root.get(o.section())->as_table();
  } else {
    to = &entryOf(root, o, file);
  }
  auto [key, node] = *from.begin();
  to->erase(o.key());
  to->insert(key, std::move(node));
}

Scene parseWith(std::string_view text, const std::string& sourceName, std::vector<Override>& overrides,
                const std::string& base = {}) {
  toml::table root = parseToml(text, sourceName);
  for (Override& o : overrides) applyOverride(root, o, sourceName);
  return SceneParser(root, sourceName, base).run();
}

}  // namespace

Scene parseScene(std::string_view text, const std::string& sourceName, const std::vector<std::string>& overrides,
                 OverrideSource source, const std::string& base) {
  std::vector<Override> parsed = parseOverrides(overrides, source);
  return parseWith(text, sourceName, parsed, base);
}

Scene readSceneFile(const std::string& path, const std::vector<std::string>& overrides, OverrideSource source) {
  std::vector<Override> parsed = parseOverrides(overrides, source);  // mistakes in the overrides first
  return parseWith(detail::readWholeFile(path, "", detail::kSceneFileLimit), path, parsed);
}

void refuseSceneInput(const Scene& scene, const std::string& path, const std::string& what) {
  if (path.empty()) return;
  auto refuse = [&](const std::string& input, const std::string& as) {
    std::error_code ec;  // (a scene parsed from text names a file it never read: only files there count)
    if (!input.empty() && std::filesystem::exists(input, ec) && sameFile(path, input))
      throw Error(what + " " + path + " is " + input + ", " + as +
                  ": writing it would destroy an input of the run; name another file");
  };
  refuse(scene.sourceFile, "the scene file");
  for (const WallDef& w : scene.walls)
    if (w.shape == WallDef::Shape::Mesh) refuse(w.meshFile, "the mesh of " + w.where);
  for (const ShapeDef& s : scene.shapes) refuse(s.meshFile, "the mesh of shape \"" + s.name + "\"");
}

}  // namespace tumble
