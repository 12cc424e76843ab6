// SPDX-License-Identifier: MIT
/// @file scene_io.hpp
/// The TOML scene format (docs/scenes.md): reading scene files into a tumble::Scene.
#pragma once
#include <string>
#include <string_view>

#include "tumble/scene.hpp"

namespace tumble {

/// Reads and validates a scene file. Throws tumble::InputError naming the file, the line and
/// the problem (missing file, TOML syntax, unknown key, wrong type, NaN/inf, radius ≤ 0,
/// mass ≤ 0, elasticity outside (0, 1], empty scene, unknown shape name).
Scene readSceneFile(const std::string& path);

/// Same as readSceneFile() on text already in memory; `sourceName` is used in messages.
Scene parseScene(std::string_view text, const std::string& sourceName);

}  // namespace tumble
