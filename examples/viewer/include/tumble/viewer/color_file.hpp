// SPDX-License-Identifier: MIT
/// @file color_file.hpp
/// A user's values to colour the bodies by (`tumble render --color-file FILE.csv`): one column,
/// a header line naming the values (the legend's name) and then one value per body, or one per
/// particle, for the whole recording. Plain C++ (no OpenGL).
#pragma once
#include <string>
#include <vector>

#include "tumble/viewer/draw_data.hpp"

namespace tumble::viewer {

/// The longest header the legend takes (characters).
inline constexpr std::size_t kMaxColorFileName = 40;

/// The values of a colour file, as read.
struct ColorFile {
  std::string origin;         ///< the file, for messages
  std::string name;           ///< the header: the legend's name ("stress kPa")
  std::vector<float> values;  ///< the rows after the header, in order (finite)
  /// One value per particle of `table`: the file's values by body (value k for every particle of
  /// body k) when it has as many as the table has bodies, else by particle when it has as many as
  /// particles. Any other count throws InputError naming both counts of `recording` (its name, for
  /// the message).
  std::vector<float> particleValues(const ParticleTable& table, const std::string& recording) const;
};

/// Parses a colour file: the first line is the header (the name the legend shows, at most
/// kMaxColorFileName characters; a UTF-8 byte-order mark, surrounding spaces and double quotes
/// are dropped), every further line one number (as strtod reads it; finite and within a float's
/// range); blank lines are allowed only at the end, and a line with a comma (two columns) is
/// refused. Throws InputError naming `origin`, the line, what is wrong and what to do.
ColorFile parseColorFile(const std::string& text, const std::string& origin);
/// parseColorFile of a file (InputError when it cannot be read).
ColorFile readColorFile(const std::string& path);

}  // namespace tumble::viewer
