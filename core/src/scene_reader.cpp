// SPDX-License-Identifier: MIT
// The TOML scene reader's shared helpers (scene_reader.hpp): table names, error locations,
// number and type text, and the lookup of array-of-tables and table-valued keys.
#include "scene_reader.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace tumble::scene_reader {

std::string tableNames(bool arrays) {
  std::string out;
  for (std::string_view t : kSingleTables) out += (out.empty() ? "[" : ", [") + std::string(t) + "]";
  return arrays ? out + ", " + arrayTableNames() : out;
}

std::string arrayTableNames() {
  std::string out;
  for (std::string_view t : kArrayTables) out += (out.empty() ? "[[" : ", [[") + std::string(t) + "]]";
  return out;
}

InputError errorAt(const std::string& file, const toml::source_region& at, const std::string& problem) {
  if (at.path != nullptr && *at.path != file) return InputError(*at.path, 0, problem);
  return InputError(file, static_cast<long>(at.begin.line), problem);
}

std::string fmt(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::array<char, 64> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v, std::chars_format::general);
  return std::string(buf.data(), res.ptr);
}

std::string typeName(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a floating-point number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

std::string joinNames(std::initializer_list<std::string_view> names) {
  std::string out;
  for (std::string_view n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::vector<const toml::table*> tablesOf(const std::string& file, const toml::node& n,
                                         const std::string& where, std::string_view header) {
  const auto* arr = n.as_array();
  if (arr == nullptr) {
    throw errorAt(file, sourceOf(n), where + " must be an array of tables: write each entry as " +
                                         std::string(header) + " (got " + typeName(n) + ")");
  }
  std::vector<const toml::table*> out;
  for (const toml::node& el : *arr) {
    const auto* t = el.as_table();
    if (t == nullptr) {
      throw errorAt(file, sourceOf(el), where + " entries must be tables, written as " +
                                            std::string(header) + " (got " + typeName(el) + ")");
    }
    out.push_back(t);
  }
  return out;
}

std::string stemOf(const std::string& path) {
  const std::string stem = std::filesystem::path(path).stem().string();
  return stem.empty() ? std::string("scene") : stem;
}

}  // namespace tumble::scene_reader
