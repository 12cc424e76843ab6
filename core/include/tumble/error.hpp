// SPDX-License-Identifier: MIT
/// @file error.hpp
/// Exceptions thrown at the API boundary (bad configuration, bad input files).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace tumble {

/// User text (a token, a key, a name, a path) as a message shows it: a NUL byte as \0, a tab,
/// newline or carriage return as \t, \n, \r, any other control byte as \xNN; the rest as is
/// (UTF-8 stays UTF-8). A NUL would otherwise end the message where what() is read as a C string.
inline std::string printable(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7f) {
      out += ch;
    } else if (c == 0) {
      out += "\\0";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

/// Configuration or input error. what() is one line meant for the user; for file input it
/// starts with "FILE:LINE: ".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An input file could not be read or parsed. Carries the file and line (0 = unknown) as given;
/// what() shows both the file and the problem printable(), so that the user text they quote (a
/// token, a key, a name, Python's name= or set=) is shown whole, on one line.
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
    std::string s = printable(file);
    if (line > 0) {
      s += ':';
      s += std::to_string(line);
    }
    s += ": ";
    s += printable(problem);
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
