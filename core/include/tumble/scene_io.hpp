// SPDX-License-Identifier: MIT
/// @file scene_io.hpp
/// The TOML scene format (docs/scenes.md): reading scene files into a tumble::Scene.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "tumble/scene.hpp"

namespace tumble {

/// Reads and validates a scene file. Throws tumble::InputError naming the file, the line and
/// the problem (missing file, TOML syntax, unknown key, wrong type, NaN/inf, radius ≤ 0,
/// mass ≤ 0, elasticity outside (0, 1], empty scene, unknown shape name).
///
/// `overrides` change keys of the file, as `tumble run --set` does (docs/scenes.md, "Overriding
/// keys on the command line"): each is "SECTION.KEY=VALUE", SECTION one of the single tables
/// ([scene], [contact], [ground], [pulls], [broadphase], [integrator], [output]) and VALUE a TOML
/// value ("0.3", "[0, 0, -9.8]", "true", "\"run.bin\""). They are applied in order, so the last
/// one of a key wins, replacing the file's value or adding the key (and its table, when the file
/// has none); the result is then checked as a file is. A problem with an override is reported
/// with file() "command line, --set SPEC" and line() 0; malformed ones (no '=', not one section
/// and one key, a [[shape]], [[body]] or [[group]] key, a VALUE that is not one TOML value) are
/// reported before the file is read.
Scene readSceneFile(const std::string& path, const std::vector<std::string>& overrides = {});

/// Throws tumble::Error when `path` is a file the scene read (its own file, a mesh's): an output
/// written there would destroy an input. `what` names the output in the message ("--state-out").
void refuseSceneInput(const Scene& scene, const std::string& path, const std::string& what);

/// Same as readSceneFile() on text already in memory; `sourceName` is used in messages.
Scene parseScene(std::string_view text, const std::string& sourceName,
                 const std::vector<std::string>& overrides = {});

}  // namespace tumble
