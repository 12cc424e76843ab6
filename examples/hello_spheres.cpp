// SPDX-License-Identifier: MIT
// hello_spheres: one file, end to end. Builds a small scene in code (a lattice of spheres falling
// onto the ground), steps it on the chosen pipeline and prints the state hash.
//   hello_spheres [--backend=cpu|cuda]
#include <cstdio>
#include <cstring>
#include <string>

#include "tumble/error.hpp"
#include "tumble/factory.hpp"
#include "tumble/random.hpp"
#include "tumble/pipeline.hpp"
#include "tumble/world.hpp"

int main(int argc, char** argv) {
  std::string backend = "cpu";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--backend=", 10) == 0) {
      backend = argv[i] + 10;
    } else {
      std::fprintf(stderr, "usage: hello_spheres [--backend=cpu|cuda]\n");
      return 2;
    }
  }
  try {
    tumble::Scene scene;
    scene.name = "hello";
    scene.dt = 1.0e-4f;
    scene.ground.enabled = true;
    scene.ground.stiffness = 1.0e5f;
    scene.contact = {1.0e5f, 5.0f, 2.0f};
    scene.shapes = {tumble::ShapeDef{"ball", {tumble::SphereDef{{0, 0, 0}, 0.1f, 0.5f, 0.6f}}}};
    tumble::Rng rng(42);
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j)
        for (int k = 0; k < 10; ++k) {
          tumble::BodyDef b;
          b.position = {0.25f * i + rng.uniform(-0.01f, 0.01f), 0.25f * j, 0.2f + 0.25f * k};
          b.velocity = {rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), 0.0f};
          scene.bodies.push_back(b);
        }
    const tumble::World world = tumble::World::fromScene(scene);
    auto pipeline = tumble::makePipeline(tumble::backendFromString(backend));
    pipeline->load(world);
    pipeline->step(2000);
    tumble::BodyState state;
    pipeline->readState(state);
    std::printf("hello_spheres: %u spheres, 2000 steps on %s, %llu contacts, state hash %016llx\n",
                world.numParticles(), backend.c_str(), static_cast<unsigned long long>(pipeline->stats().numPairs),
                static_cast<unsigned long long>(tumble::stateHash(state)));
  } catch (const tumble::Error& e) {
    std::fprintf(stderr, "hello_spheres: %s\n", e.what());
    return 2;
  }
  return 0;
}
