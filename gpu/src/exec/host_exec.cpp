// SPDX-License-Identifier: MIT
// HostStream: the host backend's emulated CUDA stream (host_exec.hpp), and the registry of live
// streams that freeing a buffer synchronises (as cudaFree synchronises the device).
#include "host_exec.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <utility>

#include "tumble/cpu/threads.hpp"

namespace tumble::gpu::exec {
namespace {

// Every live stream, so that a buffer's release can run their queues first.
std::mutex g_registryMutex;
std::vector<const HostStream*>& registry() {
  static std::vector<const HostStream*> streams;
  return streams;
}

}  // namespace

HostStream::HostStream(int threads)
    : m_allowThreads(cpu::allowThreads(threads)), m_arena(threads > 0 ? threads : tbb::task_arena::automatic) {
  const char* env = std::getenv("TUMBLE_CUDA_SYNC");
  m_syncEach = env != nullptr && std::strcmp(env, "1") == 0;
  const std::lock_guard<std::mutex> lock(g_registryMutex);
  registry().push_back(this);
}

HostStream::~HostStream() {
  {
    const std::lock_guard<std::mutex> lock(g_registryMutex);
    auto& r = registry();
    r.erase(std::find(r.begin(), r.end(), this));
  }
  // As cudaStreamDestroy: work already queued still completes.
  try {
    synchronize();
  } catch (...) {
  }
}

void HostStream::enqueue(std::function<void()> op) const {
  const std::lock_guard<std::mutex> lock(m_mutex);
  m_queue.push_back(std::move(op));
  if (m_syncEach) drainLocked();
}

void HostStream::synchronize() const {
  const std::lock_guard<std::mutex> lock(m_mutex);
  drainLocked();
}

void HostStream::abandon() const noexcept {
  const std::lock_guard<std::mutex> lock(m_mutex);
  m_queue.clear();
}

void HostStream::drainLocked() const {
  // Taken out first: a failing operation leaves the queue empty, as a CUDA error ends the work.
  std::vector<std::function<void()>> work;
  work.swap(m_queue);
  for (auto& op : work) op();
}

void HostStream::synchronizeAll() {
  const std::lock_guard<std::mutex> lock(g_registryMutex);
  for (const HostStream* s : registry()) s->synchronize();
}

void HostStream::synchronizeAllBeforeFree() noexcept {
  try {
    synchronizeAll();
  } catch (const std::exception& e) {
    // A destructor's release: nothing can be reported further up (grow() synchronises first,
    // where a failure throws).
    std::fprintf(stderr, "tumble: the host backend's queued work failed while a buffer was freed: %s\n", e.what());
    std::abort();
  }
}

}  // namespace tumble::gpu::exec
