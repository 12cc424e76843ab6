// SPDX-License-Identifier: MIT
// Small text helpers shared by the viewer's file readers (camera paths, colour files).
#pragma once
#include <string>

namespace tumble::viewer::detail {

/// `s` without the spaces, tabs and carriage returns at either end.
inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

}  // namespace tumble::viewer::detail
