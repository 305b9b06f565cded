#include "navaid/mapping/pose_uncertainty.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {
std::string at_time(const StateEstimate& e) { return "estimate at t = " + std::to_string(e.t) + " ns: "; }

void check_block(const Eigen::Matrix3d& block, const char* what, const StateEstimate& e) {
  if (!block.allFinite()) throw Error(at_time(e) + what + " covariance is not finite");
  if ((block - block.transpose()).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, block.cwiseAbs().maxCoeff()))
    throw Error(at_time(e) + what + " covariance is not symmetric");
  Eigen::LLT<Eigen::Matrix3d> llt(block);
  if (llt.info() != Eigen::Success) throw Error(at_time(e) + what + " covariance is not positive definite");
}
}  // namespace

PoseUncertainty pose_uncertainty(const StateEstimate& e) {
  if (!e.T_W_B.t.allFinite() || !e.T_W_B.q.coeffs().allFinite()) throw Error(at_time(e) + "pose is not finite");
  const Eigen::Matrix3d rot = e.covariance.block<3, 3>(0, 0);
  const Eigen::Matrix3d pos = e.covariance.block<3, 3>(3, 3);
  check_block(rot, "rotation", e);
  check_block(pos, "position", e);
  PoseUncertainty u;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> xy(pos.block<2, 2>(0, 0), Eigen::EigenvaluesOnly);
  u.sigma_xy = std::sqrt(std::max(0.0, xy.eigenvalues().maxCoeff()));
  u.sigma_z = std::sqrt(pos(2, 2));
  const Eigen::Matrix3d R = e.T_W_B.q.toRotationMatrix();
  const Eigen::Matrix3d rot_W = R * rot * R.transpose();
  u.sigma_yaw = std::sqrt(std::max(0.0, rot_W(2, 2)));
  return u;
}

namespace {
const ConfigKey<double> kMaxSigmaXy{"mapping.gate.max_sigma_xy_m", MappingGateConfig{}.max_sigma_xy_m, {0.0, 100.0},
                                    "a frame less sure than this horizontally is not mapped [m]"};
const ConfigKey<double> kMaxSigmaYaw{"mapping.gate.max_sigma_yaw_deg",
                                     MappingGateConfig{}.max_sigma_yaw_rad * 180.0 / M_PI, {0.0, 180.0},
                                     "a frame less sure than this in yaw is not mapped [deg]"};
const ConfigKey<std::string> kScope{"mapping.gate.scope", std::string("window"), {"window", "absolute"},
                                    "gate on the uncertainty gained over the window or on the absolute one"};
const ConfigKey<double> kWindow{"mapping.gate.window_s", MappingGateConfig{}.window_s, {0.1, 3600.0},
                                "scope window: the span the uncertainty gain is measured over [s]"};
}  // namespace

ConfigSchema mapping_gate_config_schema() {
  return ConfigSchema().add(kMaxSigmaXy).add(kMaxSigmaYaw).add(kScope).add(kWindow);
}

MappingGateConfig read_mapping_gate_config(const Config& c) {
  MappingGateConfig g;
  g.max_sigma_xy_m = get(c, kMaxSigmaXy);
  g.max_sigma_yaw_rad = get(c, kMaxSigmaYaw) * M_PI / 180.0;
  g.scope = get(c, kScope) == "window" ? UncertaintyScope::kWindow : UncertaintyScope::kAbsolute;
  g.window_s = get(c, kWindow);
  return g;
}

PoseUncertainty UncertaintyWindow::add(Timestamp t, const PoseUncertainty& u, double window_s) {
  if (!samples_.empty() && t < samples_.back().t) throw Error("UncertaintyWindow: times must not decrease");
  samples_.push_back({t, u});
  // Keep the newest sample at or before t - window: the reference the gain is measured from.
  const Timestamp start = t - static_cast<Timestamp>(window_s * 1e9);
  std::size_t first = 0;
  while (first + 1 < samples_.size() && samples_[first + 1].t <= start) ++first;
  samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(first));
  const PoseUncertainty& ref = samples_.front().u;
  const auto gain = [](double now, double then) { return std::sqrt(std::max(0.0, now * now - then * then)); };
  return {gain(u.sigma_xy, ref.sigma_xy), gain(u.sigma_z, ref.sigma_z), gain(u.sigma_yaw, ref.sigma_yaw)};
}

GateDecision gate(const StateEstimate& e, const PoseUncertainty& u, const MappingGateConfig& g) {
  if (e.mode == EstimatorMode::kInitializing || e.mode == EstimatorMode::kLost) return GateDecision::kSkipMode;
  if (u.sigma_xy > g.max_sigma_xy_m || u.sigma_yaw > g.max_sigma_yaw_rad) return GateDecision::kSkipUncertain;
  return GateDecision::kMap;
}

}  // namespace navaid::mapping
