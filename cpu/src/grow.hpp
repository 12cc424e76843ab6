// SPDX-License-Identifier: MIT
// Grow-only scratch columns: a step never allocates once capacities have settled.
#pragma once
#include <cstddef>
#include <vector>

namespace tumble::detail {

/// Makes v hold at least n elements (growing with 25 % slack) and returns its data. Never shrinks.
template <class T>
T* grow(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) v.resize(n + n / 4 + 16);
  return v.data();
}

}  // namespace tumble::detail
