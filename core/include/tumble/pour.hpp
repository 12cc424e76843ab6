// SPDX-License-Identifier: MIT
/// @file pour.hpp
/// Bodies that enter a run (`[[pour]]`, docs/scenes.md): each pour adds its bodies in its
/// region at `rate` bodies per second from `start`, in batches, each body placed where it
/// overlaps no body, the ground or a wall at that moment.
///
/// - Every body a pour will add, its shape (scaled), orientation and velocities are drawn when
///   the scene is read (Scene::pourBodies, in the order they are due); only its position is
///   drawn when it enters, from a generator seeded by the pour's seed, the body's index and the
///   step: a resumed run draws the same positions.
/// - A batch falls every `interval` (the smallest of the pours') from the earliest start. At a
///   batch the bodies due by then enter in their order; one that finds no place in `attempts`
///   draws waits, with every body after it, for the next batch.
/// - A body that enters is appended to the world: the run goes on from the pipeline's state
///   (read bit for bit, contact histories and wall springs included) with a pipeline loaded
///   afresh, which continues as a resumed run does: the same bits as if it had never stopped.
///   The drivers (tumble run, view, the Python module) call pour() at the batch steps.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "tumble/pipeline.hpp"
#include "tumble/scene.hpp"
#include "tumble/world.hpp"

namespace tumble {

namespace detail {
class MeshObstacles;
}

class Pouring {
 public:
  /// `scene` as read (Scene::bodies the bodies at the start, Scene::pourBodies those to come).
  explicit Pouring(const Scene& scene);
  // Its cache of the meshes refers to its scene: not copied or moved.
  Pouring(const Pouring&) = delete;
  Pouring& operator=(const Pouring&) = delete;

  /// The scene as read.
  const Scene& scene() const { return m_scene; }
  /// Whether the scene pours anything.
  bool any() const { return !m_scene.pourBodies.empty(); }
  /// Bodies at the start of the run, before any pour.
  std::size_t initialBodies() const { return m_scene.bodies.size(); }
  /// Bodies once every pour is done.
  std::size_t finalBodies() const { return m_scene.bodies.size() + m_scene.pourBodies.size(); }
  /// The shape (index into scene().shapes) of body k (< finalBodies()) of the run's worlds: the
  /// scene's bodies first, then the pours' in the order they enter.
  std::uint32_t shapeOf(std::size_t k) const {
    return k < m_scene.bodies.size() ? m_scene.bodies[k].shape : m_scene.pourBodies[k - m_scene.bodies.size()].body.shape;
  }
  /// The first batch step at or after `step` while some body has yet to enter a world of
  /// `bodies` bodies; never (UINT64_MAX) once all have.
  std::uint64_t nextBatch(std::uint64_t step, std::size_t bodies) const;
  /// Bodies due by time `t` (their pour's rate) that a world of `bodies` bodies does not hold
  /// yet. Right after a batch (enter()), those that found no place in their region: the pour has
  /// fallen behind.
  std::size_t waiting(std::size_t bodies, double t) const { return dueBy(bodies - initialBodies(), t) - (bodies - initialBodies()); }
  /// The world of the scene with its first `bodies` bodies (the initial ones, then the pour's in
  /// order), the pour's where they are due to appear (the centre of their region): the world
  /// a checkpoint of such a run resumes (Checkpoint::resume() then sets the state), and, with
  /// finalBodies(), the particle table of a recording.
  World worldWith(std::size_t bodies) const;
  /// At a batch step (nextBatch()): places the bodies due by the pipeline's time around its
  /// state and returns the world to load() to go on with them (the pipeline's state, bit for bit,
  /// and the new bodies); nothing when none entered. `world` is the world the pipeline runs.
  std::optional<World> pour(const World& world, const Pipeline& pipeline) const;
  /// At a batch step (nextBatch() is the pipeline's stepCount()): the bodies due enter (pour();
  /// `world` grows and the pipeline is loaded with it, keeping its pulls; `stats` (may be null)
  /// gains the counters it had). Returns whether the world grew; does nothing at any other step.
  bool enter(Pipeline& pipeline, World& world, StepStats* stats) const;
  /// Steps `pipeline`, which runs `world`, n steps, the bodies due entering (enter()) at each
  /// batch step before it is stepped. Returns whether the world grew. A run resumed at a batch
  /// step pours there first, as the run it continues did. (Run::advance() does the same with
  /// enter() and stretches that end before each batch step.)
  bool step(Pipeline& pipeline, World& world, std::uint64_t n, StepStats* stats) const;

 private:
  /// The first pour body at or after `first` not yet due at time t.
  std::size_t dueBy(std::size_t first, double t) const;
  /// Positions (in frame) for the pour bodies first..due, in order, until one finds no place,
  /// clear of the particles at x (3 per particle, in frame) of the given radii and the walls.
  /// `walls` and `meshPoses` (empty: the meshes where they were given) pose them at the time.
  std::vector<Vec3f> place(std::size_t first, std::size_t due, const std::vector<float>& x,
                           const std::vector<float>& radius, float maxRadius, const LocalFrame& frame,
                           const std::vector<Wall>& walls, const std::vector<MeshPose>& meshPoses,
                           std::uint64_t step) const;
  /// The world of the initial bodies, the pour bodies before `first` (at their regions' centres)
  /// and then the placed ones (positions in frame); `checkPlacement`: World::fromScene()'s.
  World withBodies(std::size_t first, const std::vector<Vec3f>& placed, const LocalFrame& frame,
                   bool checkPlacement) const;

  /// The scene's mesh walls in a frame (built at the first batch of a run that has some, and
  /// again if the frame changes).
  const detail::MeshObstacles& meshesIn(const LocalFrame& frame) const;

  Scene m_scene;
  mutable std::shared_ptr<const detail::MeshObstacles> m_meshes;
  mutable LocalFrame m_meshesFrame;
  std::uint64_t m_firstStep = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t m_everySteps = 1;
};

}  // namespace tumble
