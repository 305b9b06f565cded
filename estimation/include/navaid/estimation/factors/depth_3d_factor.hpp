#pragma once
// Depth-augmented 3D factor (W-ROMA §V-B, r_d^kj) for a feature first observed in keyframe i
// (the anchor, m_i = [x_i, y_i, 1] on the normalized plane) and tracked into keyframe j with a
// depth measurement:
//
//   measured  (camera C_j):  X = x_j Z,  Y = y_j Z,  Z    (m_j = [x_j, y_j, 1], Z from the depth image)
//   estimated (camera C_j):  [X^, Y^, Z^] = R_cj_ci m_i / lambda_i + t_cj_ci
//                            (T_cj_ci = T_B_C^-1 T_W_Bj^-1 T_W_Bi T_B_C, lambda_i the anchor's inverse depth)
//   r = S [X - X^, Y - Y^, 1/Z - 1/Z^],   S^T S = Sigma^-1
//
// Two models of Sigma (Depth3dCovariance):
//  - kPaper: Sigma = diag(sigma_x^2, sigma_y^2, sigma_lambda^2), sigma_x = sigma_y = Z sigma / f
//    (sigma: image noise, 1.5 px in the paper; f: focal length [px]; sigma_lambda = sigma_d / (f b),
//    inverse_depth_sigma(), disparity noise). It leaves out that X = x Z and Y = y Z carry the
//    depth noise too (x sigma_Z, with sigma_Z = Z^2 sigma_lambda: 2x the pixel term at 3 m near the
//    image border of a 65 mm-baseline camera) and that it is correlated with the 1/Z term.
//  - kFull: the first-order propagation of independent pixel noise (sigma / f on x, y) and
//    inverse-depth noise (sigma_lambda on 1/Z) through (x, y, 1/Z) -> (x Z, y Z, 1/Z). Its square
//    root information is upper triangular:
//      S = diag(f / sigma, f / sigma, 1 / sigma_lambda) [[1/Z, 0, x Z], [0, 1/Z, y Z], [0, 0, 1]]
//    (the inverse of that map's Jacobian, whitened): kPaper is S without the x Z, y Z terms.
//
// The paper writes the third term as 1/Z - Z^ with Z^ an inverse depth; here Z^ is the estimated
// depth and the term is the inverse-depth difference, as the covariance sigma_lambda says.
// Sigma uses the measured Z, so the weights are constant during the optimization.
// Parameter blocks: pose_i T_W_Bi (7), pose_j T_W_Bj (7), extrinsic T_B_C (7), lambda_i (1).
// Callers wrap it in a Cauchy loss. Evaluate() returns false when Z^ <= 1e-6 m.
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "navaid/estimation/factors/depth_3d_covariance.hpp"

namespace navaid::estimation {

class Depth3dFactor final : public ceres::SizedCostFunction<3, 7, 7, 7, 1> {
 public:
  /// Throws Error unless depth_j_m > 0 and ConfigError unless focal_px, sigma_px, sigma_lambda > 0.
  Depth3dFactor(const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target, double depth_j_m,
                double focal_px, double sigma_lambda, double sigma_px = 1.5,
                Depth3dCovariance model = Depth3dCovariance::kFull);

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// The same residual for other measurements m_anchor, m_target, depth_j_m (the weights stay
  /// those of the constructor's depth), with its Jacobians w.r.t. the measurements as well when
  /// d_m_anchor / d_m_target / d_depth are not null (Depth3dTdFactor moves the measurements with
  /// the time offset). Evaluate() is evaluate_at(the constructor's measurements).
  bool evaluate_at(double const* const* parameters, const Eigen::Vector2d& m_anchor, const Eigen::Vector2d& m_target,
                   double depth_j_m, double* residuals, double** jacobians, Eigen::Matrix<double, 3, 2>* d_m_anchor,
                   Eigen::Matrix<double, 3, 2>* d_m_target, Eigen::Vector3d* d_depth) const;

  /// The measured point [X, Y, 1/Z] and S (upper triangular; diagonal for kPaper).
  const Eigen::Vector3d& measurement() const { return measurement_; }
  const Eigen::Matrix3d& sqrt_information() const { return sqrt_information_; }

 private:
  Eigen::Vector2d m_anchor_, m_target_;
  double depth_m_;
  Eigen::Vector3d measurement_;
  Eigen::Matrix3d sqrt_information_;
};

}  // namespace navaid::estimation
