// SPDX-License-Identifier: MIT
/// @file mesh_mass.hpp
/// The solid a closed triangle mesh bounds (issue 36: shapes made from meshes take their mass
/// properties from the mesh itself, not from the spheres that approximate it): the checks that
/// it bounds one (every edge shared by exactly two triangles that run it in opposite
/// directions), and its volume, centroid and inertia tensor at density 1 by the divergence
/// theorem (Eberly, "Polyhedral Mass Properties (Revisited)", 2002, after Mirtich, "Fast and
/// Accurate Computation of Polyhedral Mass Properties", 1996): each triangle with the origin
/// adds a signed tetrahedron's integrals of 1, x, y, z, x², y², z², xy, yz, zx, in double.
#pragma once
#include <array>

#include "tumble/mesh.hpp"

namespace tumble {

/// The solid at density 1 (times a density: its mass properties). `inertia` is the tensor
/// about the centroid in the mesh's axes, xx, yy, zz, xy, xz, yz, its products of inertia
/// with their sign (I_xy = −∫ (x − cx)(y − cy) dV).
struct SolidProperties {
  double volume = 0.0;
  std::array<double, 3> centroid{0.0, 0.0, 0.0};
  std::array<double, 6> inertia{0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
};

/// The solid `mesh` bounds, its vertices taken times `scale` per axis (in double). Throws
/// tumble::InputError naming the file and the first triangle (in the file's order, at its line
/// or byte) of an edge that bounds no solid: an open edge (one triangle), a non-manifold one
/// (three or more), or one whose two triangles run it the same way (their orientations
/// disagree); then the first pair of triangles that cross each other (pairs sharing a vertex
/// untested; touching or coplanar ones do not count); then a piece (triangles joined by edges)
/// wound against its place: outward inside an odd number of the other pieces (a cavity) or
/// inward inside an even number (a part). A mesh wound inward as a whole (a negative volume) is
/// taken as its outward twin.
SolidProperties solidProperties(const TriangleMesh& mesh, std::array<double, 3> scale = {1.0, 1.0, 1.0});

}  // namespace tumble
