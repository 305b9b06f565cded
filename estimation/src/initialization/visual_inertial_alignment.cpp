#include "navaid/estimation/initialization/visual_inertial_alignment.hpp"

#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "navaid/core/errors.hpp"
#include "navaid/core/number_text.hpp"

namespace navaid::estimation {
namespace {

using MatX = Eigen::MatrixXd;
using VecX = Eigen::VectorXd;

void validate_input(const std::vector<Timestamp>& times, const std::vector<SE3>& T_l_C, const SE3& T_B_C,
                    const std::vector<ImuPreintegration>& pre) {
  const std::string where = "visual-inertial alignment: ";
  if (times.size() != T_l_C.size())
    throw Error(where + std::to_string(times.size()) + " keyframe times but " + std::to_string(T_l_C.size()) +
                " camera poses");
  const std::size_t expected = times.empty() ? 0 : times.size() - 1;
  if (pre.size() != expected)
    throw Error(where + std::to_string(pre.size()) + " preintegrations for " + std::to_string(times.size()) +
                " keyframes (need one between each consecutive pair: " + std::to_string(expected) + ")");
  if (!T_B_C.t.allFinite() || !T_B_C.q.coeffs().allFinite()) throw Error(where + "T_B_C is not finite");
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!T_l_C[k].t.allFinite() || !T_l_C[k].q.coeffs().allFinite())
      throw Error(where + "camera pose of keyframe " + std::to_string(k) + " is not finite");
    if (k + 1 < times.size()) {
      if (times[k + 1] <= times[k])
        throw Error(where + "keyframe times must increase strictly (keyframe " + std::to_string(k + 1) + ")");
      if (pre[k].samples().empty() || pre[k].start_time() != times[k] || pre[k].end_time() != times[k + 1])
        throw Error(where + "preintegration " + std::to_string(k) + " does not run from keyframe " +
                    std::to_string(k) + " to keyframe " + std::to_string(k + 1));
    }
  }
}

// Step 1. Each pass solves the normal equations of J_k db = Log(gamma_k^-1 R_k^T R_k+1) at the
// preintegrations' current linearization bias and integrates them again at the update, so that
// the first-order correction is only ever used for the step, not for the result.
bool estimate_gyro_bias(const std::vector<Quat>& q_l_B, std::vector<ImuPreintegration>& pre, int iterations,
                        Vec3* b_g, double* rms, std::string* failure) {
  Mat3 A;
  Vec3 rhs;
  auto linearize = [&] {
    A.setZero();
    rhs.setZero();
    double sq = 0;
    for (std::size_t k = 0; k < pre.size(); ++k) {
      const Vec3 r = so3_boxminus(q_l_B[k].conjugate() * q_l_B[k + 1], pre[k].delta_q());
      const Mat3 J = pre[k].d_theta_d_bg();
      A += J.transpose() * J;
      rhs += J.transpose() * r;
      sq += r.squaredNorm();
    }
    *rms = std::sqrt(sq / static_cast<double>(pre.size()));
  };
  for (int it = 0; it < iterations; ++it) {
    linearize();
    const Eigen::LDLT<Mat3> ldlt(A);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12)) {
      *failure = "gyro bias: singular rotation system (keyframes too close in time)";
      return false;
    }
    const Vec3 db = ldlt.solve(rhs);
    *b_g += db;
    for (auto& p : pre) p.repropagate(*b_g, p.linearization_accel_bias());
    if (db.norm() < 1e-12) break;
  }
  linearize();  // the residual at the estimate
  return true;
}

// Step 2's rows: A_x x + G g_l = b with x = [v_0 .. v_N-1, (s)]. Gravity's columns are kept apart
// so that the refinement can substitute g_l = g_0 + B w.
struct LinearSystem {
  MatX A_x;
  MatX G;
  VecX b;
};

LinearSystem build_system(const std::vector<Timestamp>& times, const std::vector<SE3>& T_l_C, const SE3& T_B_C,
                          const std::vector<Quat>& q_l_B, const std::vector<ImuPreintegration>& pre,
                          bool estimate_scale) {
  const std::size_t n = times.size();
  const int nx = static_cast<int>(3 * n) + (estimate_scale ? 1 : 0);
  const int rows = static_cast<int>(6 * (n - 1));
  LinearSystem s{MatX::Zero(rows, nx), MatX::Zero(rows, 3), VecX::Zero(rows)};
  const Vec3& t_BC = T_B_C.t;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const int r = static_cast<int>(6 * k);
    const int vi = static_cast<int>(3 * k), vj = vi + 3;
    const double dt = ns_to_seconds(times[k + 1] - times[k]);
    const Mat3 Rt = q_l_B[k].toRotationMatrix().transpose();
    const Mat3 Rj = q_l_B[k + 1].toRotationMatrix();
    const Vec3 dc = T_l_C[k + 1].t - T_l_C[k].t;
    // alpha rows
    s.A_x.block<3, 3>(r, vi) = -Rt * dt;
    s.G.block<3, 3>(r, 0) = -Rt * (0.5 * dt * dt);
    s.b.segment<3>(r) = pre[k].delta_p() + Rt * Rj * t_BC - t_BC;
    if (estimate_scale)
      s.A_x.block<3, 1>(r, nx - 1) = Rt * dc;
    else
      s.b.segment<3>(r) -= Rt * dc;
    // beta rows
    s.A_x.block<3, 3>(r + 3, vi) = -Rt;
    s.A_x.block<3, 3>(r + 3, vj) = Rt;
    s.G.block<3, 3>(r + 3, 0) = -Rt * dt;
    s.b.segment<3>(r + 3) = pre[k].delta_v();
  }
  return s;
}

// Least squares with unit-norm columns (velocities, gravity and the scale differ by orders of
// magnitude); nullopt when rank deficient.
std::optional<VecX> solve_scaled(const MatX& A, const VecX& b) {
  const VecX norms = A.colwise().norm().transpose();
  if (!(norms.minCoeff() > 0)) return std::nullopt;
  const Eigen::ColPivHouseholderQR<MatX> qr(A * norms.cwiseInverse().asDiagonal());
  if (qr.rank() < A.cols()) return std::nullopt;
  std::optional<VecX> x(qr.solve(b).cwiseQuotient(norms));
  if (!x->allFinite()) return std::nullopt;
  return x;
}

// Two unit vectors orthogonal to unit g_hat and to each other.
Eigen::Matrix<double, 3, 2> tangent_basis(const Vec3& g_hat) {
  const Vec3 a = std::abs(g_hat.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 b1 = (a - g_hat * g_hat.dot(a)).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = b1;
  B.col(1) = g_hat.cross(b1);
  return B;
}

}  // namespace

void validate(const VisualInertialAlignmentOptions& o, const std::string& source) {
  auto require = [&](bool ok, const char* key, const char* range) {
    if (!ok) throw ConfigError(source, key, std::string("must be ") + range);
  };
  require(o.min_keyframes >= 3, "min_keyframes", ">= 3");
  require(o.gravity_norm_tolerance > 0 && o.gravity_norm_tolerance < 1, "gravity_norm_tolerance", "in (0, 1)");
  require(o.max_gyro_bias > 0, "max_gyro_bias", "> 0 rad/s");
  require(o.min_scale > 0, "min_scale", "> 0");
  require(o.gyro_bias_iterations >= 1, "gyro_bias_iterations", ">= 1");
  require(o.gravity_refinement_iterations >= 0, "gravity_refinement_iterations", ">= 0");
}

VisualInertialAlignment align_visual_inertial(const std::vector<Timestamp>& times, const std::vector<SE3>& T_l_C,
                                              const SE3& T_B_C,
                                              const std::vector<ImuPreintegration>& preintegrations,
                                              const VisualInertialAlignmentOptions& o) {
  validate(o);
  validate_input(times, T_l_C, T_B_C, preintegrations);
  VisualInertialAlignment out;
  const std::size_t n = times.size();
  if (n < o.min_keyframes) {
    out.failure = "too few keyframes: " + std::to_string(n) + " (need " + std::to_string(o.min_keyframes) + ")";
    return out;
  }
  const Quat q_C_B = T_B_C.q.conjugate();
  std::vector<Quat> q_l_B(n);
  for (std::size_t k = 0; k < n; ++k) q_l_B[k] = (T_l_C[k].q * q_C_B).normalized();

  out.preintegrations = preintegrations;
  out.gyro_bias = preintegrations.front().linearization_gyro_bias();
  out.accel_bias = preintegrations.front().linearization_accel_bias();
  if (!estimate_gyro_bias(q_l_B, out.preintegrations, o.gyro_bias_iterations, &out.gyro_bias, &out.gyro_rms_rad,
                          &out.failure))
    return out;
  if (!(out.gyro_bias.norm() <= o.max_gyro_bias)) {
    out.failure = "implausible gyro bias |b_g| = " + number_text(out.gyro_bias.norm(), 4) + " rad/s (limit " +
                  number_text(o.max_gyro_bias, 4) + ")";
    return out;
  }

  const LinearSystem sys = build_system(times, T_l_C, T_B_C, q_l_B, out.preintegrations, o.estimate_scale);
  const int nx = static_cast<int>(sys.A_x.cols());
  MatX A(sys.A_x.rows(), nx + 3);
  A << sys.A_x, sys.G;
  const auto x = solve_scaled(A, sys.b);
  if (!x) {
    out.failure = "velocity/gravity system is rank deficient (too little motion)";
    return out;
  }
  const double g_norm = kGravityW.norm();
  out.gravity_l_unrefined = x->tail<3>();
  const double rel = std::abs(out.gravity_l_unrefined.norm() - g_norm) / g_norm;
  if (!(rel <= o.gravity_norm_tolerance)) {
    out.failure = "gravity norm " + number_text(out.gravity_l_unrefined.norm(), 4) + " m/s^2 is off by " + number_text(100 * rel, 4) +
                  " % (limit " + number_text(100 * o.gravity_norm_tolerance, 4) + " %)";
    return out;
  }

  // Step 3: on the sphere, two tangent unknowns instead of three.
  Vec3 g = out.gravity_l_unrefined.normalized() * g_norm;
  VecX xr = x->head(nx);
  for (int it = 0; it < o.gravity_refinement_iterations; ++it) {
    const Eigen::Matrix<double, 3, 2> B = tangent_basis(g.normalized());
    MatX Ar(sys.A_x.rows(), nx + 2);
    Ar << sys.A_x, sys.G * B;
    const auto y = solve_scaled(Ar, sys.b - sys.G * g);
    if (!y) {
      out.failure = "gravity refinement: rank deficient system";
      return out;
    }
    g = (g + B * y->tail<2>()).normalized() * g_norm;
    xr = y->head(nx);
  }
  // Velocities and scale of the last solve belong to the g before its final update: one more
  // solve with g held.
  {
    const auto y = solve_scaled(sys.A_x, sys.b - sys.G * g);
    if (!y) {
      out.failure = "velocity system is rank deficient";
      return out;
    }
    xr = *y;
  }
  out.gravity_l = g;
  out.scale = o.estimate_scale ? xr[nx - 1] : 1.0;
  if (o.estimate_scale && !(out.scale >= o.min_scale)) {
    out.failure = "estimated scale " + number_text(out.scale, 4) + " is below " + number_text(o.min_scale, 4);
    return out;
  }
  out.velocities_l.resize(n);
  for (std::size_t k = 0; k < n; ++k) out.velocities_l[k] = xr.segment<3>(static_cast<int>(3 * k));

  // Step 4: gravity onto kGravityW, then the yaw that zeroes the oldest body's heading.
  const Quat q_tilt = Quat::FromTwoVectors(g, kGravityW);
  const double yaw = yaw_of(q_tilt * q_l_B[0]);
  const Quat q_W_l = (Eigen::AngleAxisd(-yaw, Vec3::UnitZ()) * q_tilt).normalized();
  auto p_l_B = [&](std::size_t k) -> Vec3 { return out.scale * T_l_C[k].t - (q_l_B[k] * T_B_C.t); };
  out.T_W_l = SE3(q_W_l, -(q_W_l * p_l_B(0)));
  out.T_W_B.resize(n);
  out.v_W.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    out.T_W_B[k] = out.T_W_l * SE3(q_l_B[k], p_l_B(k));
    out.v_W[k] = q_W_l * out.velocities_l[k];
  }
  out.success = true;
  return out;
}

}  // namespace navaid::estimation
