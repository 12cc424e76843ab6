// SPDX-License-Identifier: MIT
/// @file fill.hpp
/// Random packing of a region with bodies that overlap nothing (`[[fill]]`, docs/scenes.md):
/// random sequential addition. Each body's shape is drawn by weight and its size scaled by a
/// factor drawn from the fill's size distribution (size_distribution.hpp); positions (and orientations) are drawn in the region until every
/// sphere of the body lies inside it, apart from every sphere placed before it (the scene's
/// bodies, then earlier fills), and out of contact with the ground and every wall. Every draw
/// comes from the fill's own generator, so the bodies are the same for a given seed on any
/// machine and thread count.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "tumble/math.hpp"
#include "tumble/scene.hpp"
#include "tumble/size_distribution.hpp"

namespace tumble {

/// The most draws of a position per body of a [[fill]] or a [[pour]] (`attempts`): a region that needs
/// more is too full to pack at random, and a larger bound would let a typo hold the load for hours.
inline constexpr std::uint64_t kMaxPlacementAttempts = 1000000;

/// One `[[fill]]` table.
struct FillDef {
  std::vector<std::uint32_t> shapes;  ///< indices into Scene::shapes
  std::vector<double> weights;        ///< one per shape, > 0: a body's shape is drawn with these odds
  std::uint64_t count = 0;            ///< bodies to place
  FillRegion region;
  SizeDistribution size = SizeDistribution::fixed(1.0f);  ///< each body's scale factor
  Vec3f velocity{0, 0, 0};
  float velocityJitter = 0.0f;        ///< each velocity component gets a uniform addition in [−vj, vj)
  bool randomOrientation = true;
  float spin = 0.0f;                  ///< rad/s about a uniformly random axis
  std::uint64_t seed = 0;
  std::uint64_t attempts = 1000;      ///< draws of a position per body before giving up (≤ kMaxPlacementAttempts)
  std::string where;                  ///< "[[fill]] #k (file:line)" for messages
};

/// Appends def.count bodies to scene.bodies, and to scene.shapes the scaled shapes they use
/// (one per shape and scale factor other than 1, named "name x factor"; masses scale with the
/// cube of the factor). Throws tumble::Error, naming def.where, how many were placed and what
/// to change, when a body finds no place in def.attempts draws.
void fillScene(Scene& scene, const FillDef& def);

}  // namespace tumble
