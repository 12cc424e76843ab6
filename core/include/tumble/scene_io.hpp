// SPDX-License-Identifier: MIT
/// @file scene_io.hpp
/// The TOML scene format (docs/scenes.md): reading scene files into a tumble::Scene.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "tumble/scene.hpp"

namespace tumble {

/// Where overrides come from, which their messages name.
enum class OverrideSource {
  CommandLine,  ///< tumble's --set: "command line, --set SPEC", advice "--set ground.friction=0.3"
  Python,       ///< the Python module's set=: "set=['SPEC']", advice "set=['ground.friction=0.3']"
};

/// Reads and validates a scene file. Throws tumble::InputError naming the file, the line and
/// the problem (missing file, TOML syntax, unknown key, wrong type, NaN/inf, radius ≤ 0,
/// mass ≤ 0, elasticity outside (0, 1], empty scene, unknown shape name).
///
/// `overrides` change keys of the file, as `tumble run --set` does (docs/scenes.md, "Overriding
/// keys on the command line"): each is "SECTION.KEY=VALUE", SECTION one of the single tables
/// ([scene], [contact], [ground], [pulls], [broadphase], [integrator], [output], [periodic]), or
/// "ARRAY[INDEX].KEY=VALUE" / "ARRAY.NAME.KEY=VALUE" for an entry of an array of tables the file
/// has ([[wall]], [[material]], …; INDEX from 0, NAME its `name` key; nested:
/// "shape.ball.sphere[0].radius=0.2"), and VALUE a TOML value ("0.3", "[0, 0, -9.8]", "true",
/// "\"run.bin\""). They are applied in order, so the last one of a key wins, replacing the file's
/// value or adding the key (and a single table, when the file has none); the result is then
/// checked as a file is. A problem with an override is reported with file() "command line,
/// --set SPEC" (`source` CommandLine) or "set=['SPEC']" (Python) and line() 0; malformed ones
/// (no '=', no key, an unknown table, a VALUE that is not one TOML value) are reported before
/// the file is read, an entry the file lacks (an index past its last, a name none has) with the
/// entries there are.
Scene readSceneFile(const std::string& path, const std::vector<std::string>& overrides = {},
                    OverrideSource source = OverrideSource::CommandLine);

/// Throws tumble::Error when `path` is a file the scene read (its own file, a mesh's): an output
/// written there would destroy an input. `what` names the output in the message ("--state-out").
void refuseSceneInput(const Scene& scene, const std::string& path, const std::string& what);

/// Same as readSceneFile() on text already in memory; `sourceName` is used in messages. A
/// relative mesh file ([[wall]] type = "mesh") is found from `base` when it is given, else from
/// the folder of `sourceName` (the working directory for a name without one, e.g. "<python>").
Scene parseScene(std::string_view text, const std::string& sourceName,
                 const std::vector<std::string>& overrides = {},
                 OverrideSource source = OverrideSource::CommandLine, const std::string& base = {});

}  // namespace tumble
