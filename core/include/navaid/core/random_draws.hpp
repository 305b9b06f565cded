#pragma once
// Random vectors drawn in a defined order. C++ leaves the order in which a function's arguments
// are evaluated unspecified, so `Vec2(d(rng), d(rng))` draws x first under clang and y first under
// GCC: one seed, two different scenes. navaid's recordings, studies and test thresholds were made
// with GCC, which evaluates the last argument first; these helpers draw in that order everywhere.
#include <Eigen/Core>

namespace navaid {

/// An N-vector whose coefficients come from `draw()`, the last coefficient drawn first.
template <int N, class Draw>
Eigen::Matrix<double, N, 1> draw_vector(Draw&& draw) {
  Eigen::Matrix<double, N, 1> v;
  for (int i = N - 1; i >= 0; --i) v(i) = draw();
  return v;
}

}  // namespace navaid
