#pragma once
// Whether every component of a GLM vector or matrix is finite: the check every loader, mutator and solid
// applies to transforms and positions before they reach the frame.
#include <cmath>

#include <glm/glm.hpp>

namespace tandem {

template <int N, class T, glm::qualifier Q>
bool allFinite(const glm::vec<N, T, Q>& v) {
  for (int i = 0; i < N; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

template <int C, int R, class T, glm::qualifier Q>
bool allFinite(const glm::mat<C, R, T, Q>& m) {
  for (int c = 0; c < C; ++c)
    if (!allFinite(m[c])) return false;
  return true;
}

}  // namespace tandem
