// SPDX-License-Identifier: MIT
/// @file scene_io.cpp
/// TOML scene reader (schema: docs/scenes.md).
/// This file: the entry points, the TOML parse and its pre-check, the --set overrides, and
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
#include <filesystem>
#include <string>
#include <string_view>
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
  return scene;
}

}  // namespace tumble::scene_reader

namespace tumble {
namespace {

using scene_reader::isOneOf;
using scene_reader::kArrayTables;
using scene_reader::kSingleTables;
using scene_reader::SceneParser;
using scene_reader::sectionOf;
using scene_reader::tableNames;

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

/// A --set override, parsed: the document "[SECTION]\nKEY = VALUE" whose nodes have the
/// override's origin as their source path, so that the reader's messages name it.
struct Override {
  std::string origin;  // "command line, --set SPEC"
  std::string section, key;
  toml::table doc;
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

Override parseOverride(const std::string& spec) {
  Override o;
  o.origin = "command line, --set " + spec;
  const std::string_view text = spec;
  const std::size_t eq = text.find('=');
  const std::string_view name = trimmed(text.substr(0, eq));
  const std::size_t dot = name.find('.');
  if (eq == std::string_view::npos || dot == std::string_view::npos || !isBareKey(name.substr(0, dot)) ||
      !isBareKey(name.substr(dot + 1))) {
    throw InputError(o.origin, 0,
                     "expected SECTION.KEY=VALUE, one table and one of its keys (letters, digits, _ and -) and "
                     "a TOML value, e.g. --set ground.friction=0.3");
  }
  o.section = std::string(name.substr(0, dot));
  o.key = std::string(name.substr(dot + 1));
  if (!isOneOf(kSingleTables, o.section)) {
    throw InputError(o.origin, 0,
                     (isOneOf(kArrayTables, o.section)
                          ? "[[" + o.section + "]] entries cannot be set from the command line (a scene may have "
                                                "several: edit the file)"
                          : "unknown section '" + o.section + "'") +
                         "; --set can change the keys of " + tableNames(false));
  }
  const std::string_view value = text.substr(eq + 1);
  try {
    o.doc = parseToml("[" + o.section + "]\n" + o.key + " = " + std::string(value) + "\n", o.origin);
  } catch (const InputError& e) {
    const std::string_view v = trimmed(value);
    const bool bare = v.empty() || std::string_view("\"'[{").find(v.front()) == std::string_view::npos;
    throw InputError(o.origin, 0,
                     e.problem() + (bare ? "; VALUE is TOML: a string needs quotes, e.g. --set "
                                           "output.record='\"run.bin\"'"
                                         : ""));
  }
  const toml::table* t = o.doc.get_as<toml::table>(o.section);
  if (o.doc.size() != 1 || t == nullptr || t->size() != 1) {
    throw InputError(o.origin, 0, "VALUE must be one TOML value, not more keys or tables");
  }
  return o;
}

std::vector<Override> parseOverrides(const std::vector<std::string>& specs) {
  std::vector<Override> out;
  out.reserve(specs.size());
  for (const std::string& spec : specs) out.push_back(parseOverride(spec));
  return out;
}

/// Puts the override's key into the file's table (creating the table when the file lacks it),
/// replacing the file's value: moved, not copied, so that the nodes keep their source.
void applyOverride(toml::table& root, Override& o, const std::string& file) {
  toml::table& from = *o.doc.get_as<toml::table>(o.section);
  toml::node* existing = root.get(o.section);
  if (existing == nullptr) {
    root.insert(o.section, std::move(from));
    return;
  }
  (void)sectionOf(file, root, o.section);  // the file's own error when it is not a table there
  toml::table& to = *existing->as_table();
  auto [key, node] = *from.begin();
  to.erase(o.key);
  to.insert(key, std::move(node));
}

Scene parseWith(std::string_view text, const std::string& sourceName, std::vector<Override>& overrides) {
  toml::table root = parseToml(text, sourceName);
  for (Override& o : overrides) applyOverride(root, o, sourceName);
  return SceneParser(root, sourceName).run();
}

}  // namespace

Scene parseScene(std::string_view text, const std::string& sourceName, const std::vector<std::string>& overrides) {
  std::vector<Override> parsed = parseOverrides(overrides);
  return parseWith(text, sourceName, parsed);
}

Scene readSceneFile(const std::string& path, const std::vector<std::string>& overrides) {
  std::vector<Override> parsed = parseOverrides(overrides);  // mistakes on the command line first
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
}

}  // namespace tumble
