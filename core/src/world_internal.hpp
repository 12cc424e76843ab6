// SPDX-License-Identifier: MIT
// What the World's files (world.cpp, world_periodic.cpp) share. Internal to tumble_core.
#pragma once
#include "tumble/scene.hpp"

namespace tumble::detail {

// The largest shapeExtent over the shapes the scene's bodies use (those that pour in too).
double largestExtent(const Scene& scene);

}  // namespace tumble::detail
