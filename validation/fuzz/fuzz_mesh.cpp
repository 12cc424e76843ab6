// SPDX-License-Identifier: MIT
// libFuzzer target: the mesh reader (mesh.hpp). Any input is read or refused with
// tumble::InputError, as an STL and as an OBJ; a mesh that is read has its indices in range and
// its vertices finite, and for one of at most 4096 triangles the kernels' data builds (or is
// refused with tumble::Error: a triangle degenerate in single precision) and the hierarchy's
// query gives the brute-force oracle's mesh contacts for spheres around it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.hpp"
#include "tumble/error.hpp"
#include "tumble/mesh.hpp"
#include "tumble/validation/brute_force.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tumble;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  for (const char* name : {"fuzz.stl", "fuzz.obj"}) {
    TriangleMesh m;
    try {
      m = parseMesh(bytes, name);
    } catch (const InputError&) {
      continue;
    }
    if (m.numTriangles() == 0 || m.source.size() != m.numTriangles()) fuzz::fail("a mesh read without triangles");
    for (std::uint32_t i : m.triangles)
      if (i >= m.vertices.size()) fuzz::fail("a triangle names a vertex the mesh does not have");
    for (const Vec3f& v : m.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fuzz::fail("a vertex is not finite");
    if (m.numTriangles() > 4096) continue;
    Scene s;
    WallDef w;
    w.shape = WallDef::Shape::Mesh;
    w.mesh = std::make_shared<const TriangleMesh>(m);
    s.walls = {w};
    KernelMesh km;
    try {
      km = kernelMesh(s, LocalFrame{});
    } catch (const InputError&) {
      fuzz::fail("kernelMesh threw an InputError");
    } catch (const Error&) {
      continue;  // a triangle degenerate in single precision: refused with a message
    }
    // Spheres at the vertices and the triangles' centres, of the size of the mesh's triangles.
    std::vector<float> x, r;
    for (std::size_t t = 0; t < m.numTriangles() && r.size() < 64; ++t) {
      const MeshTriangle& tr = km.tri[t];
      const float size = std::max({tr.hi.x - tr.lo.x, tr.hi.y - tr.lo.y, tr.hi.z - tr.lo.z});
      const Vec3f c = km.vertices[km.triangles[3 * t]];
      if (!(size > 0.0f) || !std::isfinite(size)) continue;
      x.insert(x.end(), {c.x + 0.25f * size, c.y, c.z + 0.1f * size});
      r.push_back(0.5f * size);
    }
    if (findMeshContacts(km, x, r) != validation::bruteForceMeshContacts(km, x, r))
      fuzz::fail("the hierarchy's mesh contacts differ from the brute-force oracle's");
    (void)pointInsideMesh(km, s, 0, Vec3f{0.0f, 0.0f, 0.0f});
  }
  return 0;
}
