// SPDX-License-Identifier: MIT
/// @file error.hpp
/// Exceptions thrown at the API boundary (bad configuration, bad input files).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>

namespace tumble {

/// Configuration or input error. what() is one line meant for the user; for file input it
/// starts with "FILE:LINE: ".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An input file could not be read or parsed. Carries the file and line (0 = unknown).
class InputError : public Error {
 public:
  InputError(const std::string& file, long line, const std::string& problem)
      : Error(message(file, line, problem)), m_file(file), m_line(line), m_problem(problem) {}
  const std::string& file() const noexcept { return m_file; }
  long line() const noexcept { return m_line; }
  const std::string& problem() const noexcept { return m_problem; }

 private:
  // Built by appending (GCC 12 warns, wrongly, about chains of temporaries: -Wrestrict).
  static std::string message(const std::string& file, long line, const std::string& problem) {
    std::string s = file;
    if (line > 0) {
      s += ':';
      s += std::to_string(line);
    }
    s += ": ";
    s += problem;
    return s;
  }
  std::string m_file;
  long m_line;
  std::string m_problem;
};

/// The chosen pipeline does not run this scene's model yet (the CUDA pipeline and a contact law,
/// walls or periodic boundaries it does not have): what() names what and the pipeline that does.
class NotSupported : public Error {
 public:
  using Error::Error;
};

/// The simulation left its valid range (non-finite state and the like).
class SimulationError : public Error {
 public:
  using Error::Error;
  /// particle: the first particle found in a bad state (its index), when known.
  SimulationError(const std::string& what, std::int64_t particle) : Error(what), m_particle(particle) {}
  /// The particle found in a bad state, or −1.
  std::int64_t particle() const { return m_particle; }

 private:
  std::int64_t m_particle = -1;
};

}  // namespace tumble
