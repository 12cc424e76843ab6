// SPDX-License-Identifier: MIT
/// @file stop_signal.hpp
/// SIGINT and SIGTERM during long work (run, render): the first asks the work to stop after
/// the step or frame under way, so that it can finish its outputs; a second one of either ends
/// the process at once. SIGPIPE is ignored meanwhile, so that a reader that goes away (a FIFO,
/// ffmpeg) gives a write error to report instead of a silent death. A signal the caller chose to
/// ignore (nohup, a background job's SIGINT) stays ignored.
#pragma once
#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "tumble/output_file.hpp"

namespace tumble::cli {

/// The signal that asked to stop (0: none).
inline volatile std::sig_atomic_t g_stopSignal = 0;

/// Seconds a write under way at the first signal gets to finish before it is interrupted.
inline constexpr unsigned kWriteGraceSeconds = 2;

class StopOnSignal {
 public:
  /// restart: blocking system calls resume after the first signal (SA_RESTART), for work whose
  /// writes should finish what they started (run's recording: a frame to a pipe is written whole
  /// if its reader keeps reading). The first signal also requests a write stop and sets an alarm:
  /// a write still blocked kWriteGraceSeconds later (a pipe nobody reads) is interrupted then
  /// and gives up (writeFully, output_file.hpp), so the stop never waits forever. Without
  /// restart (render's pipe to ffmpeg, which handles EINTR itself) the signal wakes the write.
  explicit StopOnSignal(bool restart) {
    g_stopSignal = 0;
    clearWriteStop();
    struct sigaction sa {};
    sa.sa_handler = [](int sig) {
      if (g_stopSignal != 0) {  // the second: end now
        std::signal(SIGINT, SIG_DFL);
        std::signal(SIGTERM, SIG_DFL);
        std::raise(sig);
        return;
      }
      g_stopSignal = sig;
      requestWriteStop();
      ::alarm(kWriteGraceSeconds);
    };
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = restart ? SA_RESTART : 0;
    ::sigaction(SIGINT, &sa, &m_int);
    ::sigaction(SIGTERM, &sa, &m_term);
    struct sigaction wake {};  // interrupts a blocked write (no SA_RESTART), nothing else
    wake.sa_handler = [](int) {};
    sigemptyset(&wake.sa_mask);
    ::sigaction(SIGALRM, &wake, &m_alrm);
    if (m_int.sa_handler == SIG_IGN) ::sigaction(SIGINT, &m_int, nullptr);
    if (m_term.sa_handler == SIG_IGN) ::sigaction(SIGTERM, &m_term, nullptr);
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    ::sigaction(SIGPIPE, &ign, &m_pipe);
  }
  ~StopOnSignal() {
    ::alarm(0);
    ::sigaction(SIGINT, &m_int, nullptr);
    ::sigaction(SIGTERM, &m_term, nullptr);
    ::sigaction(SIGALRM, &m_alrm, nullptr);
    ::sigaction(SIGPIPE, &m_pipe, nullptr);
    clearWriteStop();
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  struct sigaction m_int {}, m_term {}, m_alrm {}, m_pipe {};
};

/// Ends the process by `sig` itself once the outputs are finished, so that a calling shell sees
/// the signal (a script stops at Ctrl-C) and the status is 128 + sig.
[[noreturn]] inline void dieOfSignal(int sig) {
  ::alarm(0);
  std::signal(SIGALRM, SIG_IGN);
  std::fflush(nullptr);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
  std::_Exit(128 + sig);
}

}  // namespace tumble::cli
