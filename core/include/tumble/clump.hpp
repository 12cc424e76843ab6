// SPDX-License-Identifier: MIT
/// @file clump.hpp
/// A clump of overlapping spheres that approximates the solid a closed triangle mesh bounds
/// (issue 36: `tumble clump`), by the Euclidean distance-transform method of the CLUMP library
/// (Angelidakis, Nadimi and Utili, "CLUMP: A Code Library to generate Universal Multi-sphere
/// Particles", SoftwareX 15 (2021) 100735; docs/model.md#shapes-from-meshes):
///
/// 1. The solid is sampled on a grid of cubic voxels (`resolution` along its longest side): a
///    voxel is inside when its sample point is (parity of the crossings of a line along x, the
///    lines offset from the voxel centres by a small irrational fraction of a voxel so that
///    they meet no edge or vertex of a mesh on round coordinates).
/// 2. The exact squared Euclidean distance transform of the inside voxels (Felzenszwalb and
///    Huttenlocher, "Distance Transforms of Sampled Functions", Theory of Computing 8 (2012)),
///    in whole voxels: each inside voxel's distance to the nearest outside one, its depth.
/// 3. Greedily, the deepest voxel not yet covered (ties: the lowest index) gets a sphere: from
///    its sample point, the centre climbs to where the exact distance to the mesh's triangles is
///    largest within a voxel of it (steps along the axes, from half a voxel down to 1/64, none
///    longer than half the radius), and the radius is that distance (so every sphere lies inside the solid and
///    touches its surface); the voxels inside the sphere are covered. Until `spheres` spheres
///    are placed, or (`tolerance`) no uncovered voxel is deeper than the tolerance (its depth in
///    voxels bounds its distance to the surface from above), or every voxel is covered. No
///    sphere is placed for a voxel whose point is under half a voxel or (`tolerance`) within the
///    tolerance from the surface (the voxel is covered), nor for one within a sphere placed
///    before, before or after its climb (reaching less than a quarter voxel out of it: the
///    voxels in its ball are covered).
///
/// `fill = Surface` places a layer instead (the surface fill): spheres of one radius ρ whose
/// centres lie at the depth ρ (within half a voxel; a voxel's depth taken as its distance to the
/// outside less half a voxel), so that each touches the surface from within, chosen by
/// farthest-point sampling (the shell's extremes first: a box's corners, then its edges) until
/// every voxel of that shell is within a spacing s of a centre; in parts thinner than 2ρ the
/// voxels of their ridge (none of the 26 neighbours deeper) stand in for the shell, each sphere
/// as deep as it is. With a tolerance D: E = D − 1.5 voxels (the grain the voxels add), which
/// must exceed 1.5 voxels (else refused, with the resolution it needs), s = √(E² + 2Eρ − 2ρ²)
/// (a box's corner then lies within E of a centre s along the layer from its own corner), and
/// of the radii 1.1, 0.9, 0.7, 0.5 and 0.35 E (within 1.5 voxels and the solid's depth) the one
/// whose layer, measured as clumpQuality() does, meets D with the fewest spheres. With a sphere
/// count N (alone, or when D's layer needs more than N): s = √2 ρ and the smallest ρ whose layer
/// has at most N spheres (bisection). Each sphere's radius is the exact distance from its centre
/// to the triangles. The inside holds no sphere: a hollow clump for the contacts of its surface,
/// whose thin parts and flat faces the inside fill covers poorly (a plate thinner than two
/// voxels gets no sphere there).
///
/// Deterministic: integer depths, fixed orders, every distance in double; the same spheres on
/// any machine and thread count (it runs on one).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tumble/mesh.hpp"
#include "tumble/mesh_mass.hpp"
#include "tumble/scene.hpp"

namespace tumble {

/// Where a clump's spheres go: filling the solid, deepest first, or as a layer under its surface.
enum class ClumpFill : std::uint8_t { Inside, Surface };

/// "inside" / "surface".
const char* toString(ClumpFill fill);

struct ClumpOptions {
  std::uint32_t spheres = 0;      ///< at most this many spheres (0: no bound)
  /// Inside: stop when no uncovered voxel is deeper than this; Surface: the deviation the layer's
  /// radius is chosen for (m; 0: no bound).
  double tolerance = 0.0;
  std::uint32_t resolution = 64;  ///< voxels along the solid's longest side (8 to 512)
  ClumpFill fill = ClumpFill::Inside;
};

struct ClumpSphere {
  std::array<double, 3> centre{0.0, 0.0, 0.0};
  double radius = 0.0;
};

/// How well a clump approximates its mesh (measured against the mesh, not the voxels):
/// `volumeRatio` the volume of the union of the spheres (its voxels' count times their volume,
/// on the grid of the construction) over the mesh's; `largestDeviation` and `meanDeviation` the
/// largest and mean distance from the mesh's surface to the clump (points on every triangle at
/// most a voxel apart; the one-sided Hausdorff distance from the surface: the clump lies inside
/// the solid, so this is how far the surface is from it).
struct ClumpQuality {
  double volumeRatio = 0.0;
  double largestDeviation = 0.0;
  double meanDeviation = 0.0;
  std::size_t samples = 0;  ///< surface points measured
};

struct Clump {
  std::vector<ClumpSphere> spheres;  ///< in the mesh's frame (scaled), deepest first
  SolidProperties solid;             ///< the mesh's solid at density 1 (solidProperties())
  ClumpQuality quality;
  double voxel = 0.0;                ///< the voxel's edge (m)
  /// Where the sphere count ended the placement: the depth (m, in voxels, as the tolerance
  /// compares it) of the deepest part of the solid left uncovered; 0 when the spheres cover the
  /// solid to within the tolerance (or to half a voxel). The inside fill only.
  double uncoveredDepth = 0.0;
  /// The surface fill: the layer's radius ρ (m).
  double layerRadius = 0.0;
};

/// The clump of `mesh` (its vertices times `scale` per axis). Throws tumble::InputError for a
/// mesh that bounds no solid (solidProperties()), and tumble::Error for options out of range
/// (neither spheres nor tolerance, a resolution outside [8, 512]).
Clump clumpFromMesh(const TriangleMesh& mesh, const ClumpOptions& options,
                    std::array<double, 3> scale = {1.0, 1.0, 1.0});

/// The quality of any spheres against `mesh` (scaled), sampled and counted with voxels of edge
/// `voxel` (clumpFromMesh() measures its own so).
ClumpQuality clumpQuality(const TriangleMesh& mesh, const std::vector<ClumpSphere>& spheres, double voxel,
                          double meshVolume, std::array<double, 3> scale = {1.0, 1.0, 1.0});

/// The shape of a clump: its spheres (offsets in the mesh's frame, rounded to float) and the
/// mesh's solid at `density` (kg/m³) as its mass properties, each sphere's mass its share by
/// volume (shareMassByVolume()). Elasticity and material as a [[shape.sphere]]'s defaults.
ShapeDef clumpShape(const Clump& clump, const std::string& name, double density);

/// A shape as the [[shape]] table of a scene file (what `tumble clump` writes): its name, its
/// solid's mass, centre_of_mass and inertia (a shape with one), then each sphere's offset and
/// radius (and mass, a shape without a solid), the floats to 9 significant digits and the
/// solid's doubles to 17 (each read back bit for bit: the table gives the shape `mesh = ` makes);
/// `comment`'s lines first, each as a TOML comment.
std::string shapeToml(const ShapeDef& shape, const std::string& comment);

}  // namespace tumble
