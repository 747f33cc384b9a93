// Run-time counts as compile-time sizes: the filters keep every matrix fixed-size (no heap
// allocation per step), so code whose size depends on how many feet are in stance is instantiated
// once per count and chosen at run time.
#pragma once

#include <type_traits>
#include <utility>

namespace legkit {

// Calls f(std::integral_constant<int, n>) for the run-time n in [N, Max]; an n above Max is
// taken as Max.
template <int Max, int N = 0, typename F>
void withFixedSize(int n, F&& f) {
  if constexpr (N == Max) {
    f(std::integral_constant<int, N>{});
  } else if (n == N) {
    f(std::integral_constant<int, N>{});
  } else {
    withFixedSize<Max, N + 1>(n, std::forward<F>(f));
  }
}

}  // namespace legkit
