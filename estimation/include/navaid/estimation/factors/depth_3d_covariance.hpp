#pragma once
// Which covariance the depth-augmented 3D factor gives its measured point [x Z, y Z, 1/Z]
// (depth_3d_factor.hpp has both formulas).

namespace navaid::estimation {

enum class Depth3dCovariance {
  kFull,   ///< pixel and inverse-depth noise propagated through the point (correlated terms)
  kPaper,  ///< W-ROMA's diag(Z sigma / f, Z sigma / f, sigma_lambda)^2
};

}  // namespace navaid::estimation
