#include "navaid/planning/hand_guidance.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/pose_uncertainty.hpp"
#include "navaid/planning/angles.hpp"
#include "navaid/planning/config_schema.hpp"

namespace navaid::planning {

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

double median_of(std::vector<double>& v) {
  const std::size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2), v.end());
  const double hi = v[n / 2];
  if (n % 2 == 1) return hi;
  const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n / 2));
  return 0.5 * (lo + hi);
}

/// The estimate's [dtheta, dp] covariance with the rotation error moved into W.
Mat6 pose_cov_W(const StateEstimate& e) {
  Mat6 G = Mat6::Identity();
  G.topLeftCorner<3, 3>() = e.T_W_B.rotation();
  const Mat6 c = G * e.covariance.topLeftCorner<6, 6>() * G.transpose();
  return 0.5 * (c + c.transpose());
}

/// The nearest positive semi-definite matrix (negative eigenvalues set to 0).
Mat6 psd_floor(const Mat6& m) {
  const Eigen::SelfAdjointEigenSolver<Mat6> es(0.5 * (m + m.transpose()));
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
}

double max_sigma(const Mat3& c) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (c + c.transpose()));
  return std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
}

double lateral_sigma(const Mat3& cov_H) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (cov_H.topLeftCorner<2, 2>() +
                                                                 cov_H.topLeftCorner<2, 2>().transpose()));
  return std::sqrt(std::max(0.0, es.eigenvalues().maxCoeff()));
}

bool pose_usable(EstimatorMode mode) { return mode != EstimatorMode::kInitializing && mode != EstimatorMode::kLost; }

}  // namespace

DepthPatchStats depth_patch_stats(const ImageF32& depth, const Eigen::Vector2d& centre_px, int half_px,
                                  double depth_min_m, double depth_max_m) {
  DepthPatchStats s;
  if (depth.empty() || !centre_px.allFinite()) return s;
  const int cu = static_cast<int>(std::lround(centre_px.x()));
  const int cv = static_cast<int>(std::lround(centre_px.y()));
  std::vector<double> values;
  for (int v = std::max(0, cv - half_px); v <= std::min(depth.height - 1, cv + half_px); ++v) {
    for (int u = std::max(0, cu - half_px); u <= std::min(depth.width - 1, cu + half_px); ++u) {
      ++s.total;
      const double d = depth.at(u, v);
      if (std::isfinite(d) && d > 0.0 && d >= depth_min_m && d <= depth_max_m) values.push_back(d);
    }
  }
  s.valid = static_cast<int>(values.size());
  if (values.empty()) return s;
  s.median_m = median_of(values);
  for (double& d : values) d = std::abs(d - s.median_m);
  s.spread_m = 1.4826 * median_of(values);
  return s;
}

namespace {
const HandGuidanceConfig kHandGuidanceDefaults;
const ConfigKey<int> kPatchHalf{"planning.hand.patch_half_px", kHandGuidanceDefaults.patch_half_px, 0, 50,
                                "half-size of the depth patch around a detection's centre [px]"};
const ConfigKey<double> kMinValidFraction{"planning.hand.min_valid_fraction", kHandGuidanceDefaults.min_valid_fraction, {1e-6, 1.0},
                                          "fewest valid depth pixels in the patch, as a fraction"};
const ConfigKey<double> kPixelSigma{"planning.hand.pixel_sigma_px", kHandGuidanceDefaults.pixel_sigma_px, {0.0, 20.0},
                                    "noise of a detection's centre [px]"};
const ConfigKey<double> kMinDepthSigma{"planning.hand.min_depth_sigma_m", kHandGuidanceDefaults.min_depth_sigma_m, {0.0, 1.0},
                                       "floor on the target's depth sigma [m]"};
const ConfigKey<double> kHandGuidanceMaxHeadingSigma{"planning.hand.max_heading_sigma_deg", rad_to_deg(kHandGuidanceDefaults.max_heading_sigma_rad),
                                         {0.1, 180.0}, "hand guidance waits while the heading sigma exceeds this [deg]"};
const ConfigKey<double> kMaxPositionSigma{"planning.hand.max_position_sigma_m", kHandGuidanceDefaults.max_position_sigma_m,
                                          {0.001, 100.0}, "hand guidance waits while the position sigma exceeds this [m]"};
const ConfigKey<double> kMaxTargetSigma{"planning.hand.max_target_sigma_m", kHandGuidanceDefaults.max_target_sigma_m, {0.001, 100.0},
                                        "hand guidance waits while the target's lateral sigma exceeds this [m]"};
const ConfigKey<double> kConfidenceSigma{"planning.hand.confidence_sigma_m", kHandGuidanceDefaults.confidence_sigma_m,
                                         {0.001, 100.0}, "hand guidance confidence falls to 0 at this lateral sigma [m]"};
const ConfigKey<std::string> kHandGuidanceScope{"planning.hand.scope", std::string("since-seen"), {"since-seen", "absolute"},
                                    "judge the uncertainty gained since the target was seen or the absolute one"};
}  // namespace

ConfigSchema hand_guidance_config_schema() {
  return hand_sector_config_schema()
      .add(kPatchHalf)
      .add(kMinValidFraction)
      .add(kPixelSigma)
      .add(kMinDepthSigma)
      .add(kHandGuidanceMaxHeadingSigma)
      .add(kMaxPositionSigma)
      .add(kMaxTargetSigma)
      .add(kConfidenceSigma)
      .add(kHandGuidanceScope);
}

HandGuidanceConfig read_hand_guidance_config(const Config& config) {
  HandGuidanceConfig c;
  c.sector = read_hand_sector_config(config);
  c.patch_half_px = get(config, kPatchHalf);
  c.min_valid_fraction = get(config, kMinValidFraction);
  c.pixel_sigma_px = get(config, kPixelSigma);
  c.min_depth_sigma_m = get(config, kMinDepthSigma);
  c.max_heading_sigma_rad = deg_to_rad(get(config, kHandGuidanceMaxHeadingSigma));
  c.max_position_sigma_m = get(config, kMaxPositionSigma);
  c.max_target_sigma_m = get(config, kMaxTargetSigma);
  c.confidence_sigma_m = get(config, kConfidenceSigma);
  c.scope = get(config, kHandGuidanceScope) == "since-seen" ? HandGuidanceScope::kSinceSeen : HandGuidanceScope::kAbsolute;
  return c;
}

TargetDetection target_from_tag(const AprilTagDetection& tag, const ImageF32& depth, int patch_half_px,
                                double depth_min_m, double depth_max_m) {
  TargetDetection d{tag.centre_px, tag.corners_px, std::nullopt};
  if (!depth.empty()) d.depth = depth_patch_stats(depth, tag.centre_px, patch_half_px, depth_min_m, depth_max_m);
  return d;
}

HandGuidance::HandGuidance(const HandGuidanceConfig& config, const CameraModel& camera, const SE3& T_H_C)
    : config_(config),
      camera_(camera),
      T_H_C_(T_H_C),
      T_B_C_(camera.calibration().T_B_C),
      depth_min_m_(camera.calibration().depth_max_m > 0.0 ? camera.calibration().depth_min_m : 0.3),
      depth_max_m_(camera.calibration().depth_max_m > 0.0 ? camera.calibration().depth_max_m : 5.0) {}

GuidanceCommand HandGuidance::update(const StateEstimate& estimate, const std::optional<TargetDetection>& detection) {
  GuidanceCommand cmd;
  cmd.t = estimate.t;
  const Mat3 R_H_C = T_H_C_.rotation();

  // The command for a target centre in H with its covariance (cases I and III).
  const auto metric_command = [&](const Vec3& P_H, const Mat3& cov_H, GuidanceReason reason, const char* label) {
    const double sigma = lateral_sigma(cov_H);
    cmd.target_H = P_H;
    cmd.confidence = std::clamp(1.0 - sigma / config_.confidence_sigma_m, 0.0, 1.0);
    if (hand_aligned(P_H, config_.sector) && P_H.z() <= config_.sector.reach_distance_m) {
      cmd.action = GuidanceAction::kArrived;
      cmd.reason = GuidanceReason::kTargetReached;
      cmd.hand = HandDirection::kHold;
    } else {
      cmd.action = GuidanceAction::kGo;
      cmd.reason = reason;
      cmd.hand = hand_direction(P_H, config_.sector);
    }
    cmd.detail = fmt::format("{}: P_H ({:.3f}, {:.3f}, {:.3f}) m, lateral sigma {:.3f} m", label, P_H.x(), P_H.y(),
                             P_H.z(), sigma);
    return cmd;
  };

  std::optional<Vec3> ray_C;
  if (detection) {
    ray_C = camera_.unproject(detection->centre_px);
    if (!ray_C) throw Error(fmt::format("hand guidance: detection centre ({:.1f}, {:.1f}) does not unproject",
                                        detection->centre_px.x(), detection->centre_px.y()));
  }

  // Case I: detected with enough depth around the centre.
  if (detection && detection->depth && detection->depth->valid > 0 &&
      detection->depth->valid >= config_.min_valid_fraction * detection->depth->total &&
      detection->depth->median_m >= depth_min_m_ && detection->depth->median_m <= depth_max_m_) {
    const DepthPatchStats& d = *detection->depth;
    const double z = d.median_m;
    const Vec3 n = *ray_C / ray_C->z();  // (x_n, y_n, 1)
    const Vec3 P_C = z * n;
    const CameraCalibration& cal = camera_.calibration();
    double model_sigma = 0.0;
    if (cal.depth_baseline_m > 0.0 && cal.depth_disparity_sigma_px > 0.0) {
      model_sigma = z * z * cal.depth_disparity_sigma_px / (cal.fx * cal.depth_baseline_m);
    }
    const double sigma_z = std::max(config_.min_depth_sigma_m,
                                    std::sqrt(model_sigma * model_sigma + d.spread_m * d.spread_m / d.valid));
    const double su = config_.pixel_sigma_px * z / cal.fx;
    const double sv = config_.pixel_sigma_px * z / cal.fy;
    Mat3 cov_C = sigma_z * sigma_z * n * n.transpose();
    cov_C(0, 0) += su * su;
    cov_C(1, 1) += sv * sv;
    const Vec3 P_H = T_H_C_ * P_C;
    const Mat3 cov_H = R_H_C * cov_C * R_H_C.transpose();

    // Remember it in W for case III when the pose is usable.
    const Mat6 pose_cov = pose_cov_W(estimate);
    if (pose_usable(estimate.mode) && pose_cov.allFinite()) {
      const SE3 T_W_C = estimate.T_W_B * T_B_C_;
      const Mat3 R_W_C = T_W_C.rotation();
      RememberedTarget r;
      r.t = estimate.t;
      r.P_W = T_W_C * P_C;
      r.measurement_cov_W = R_W_C * cov_C * R_W_C.transpose();
      r.pose_cov_W = pose_cov;
      remembered_ = r;
    }
    return metric_command(P_H, cov_H, GuidanceReason::kTargetInView, "case I (depth patch)");
  }

  // Case II: detected, no usable depth: the bearing only.
  if (detection) {
    const Vec3 ray_H = R_H_C * *ray_C;
    const Vec3 ray_B = T_B_C_.q * *ray_C;
    cmd.action = GuidanceAction::kGo;
    cmd.reason = GuidanceReason::kTargetFar;
    cmd.hand = hand_direction_of_bearing(ray_H, config_.sector);
    cmd.heading_rad = std::atan2(ray_B.y(), ray_B.x());
    cmd.confidence = 1.0;
    const DepthPatchStats d = detection->depth.value_or(DepthPatchStats{});
    cmd.detail = fmt::format("case II (beyond the depth range): walk towards it; bearing {:.1f} deg, depth {}/{} valid",
                             rad_to_deg(*cmd.heading_rad), d.valid, d.total);
    return cmd;
  }

  // Case III: not in view, remembered.
  if (!remembered_) {
    cmd.action = GuidanceAction::kWait;
    cmd.reason = GuidanceReason::kTargetNotSeen;
    cmd.detail = "the target has not been seen yet";
    return cmd;
  }
  const auto locating = [&](std::string detail) {
    cmd.action = GuidanceAction::kWait;
    cmd.reason = GuidanceReason::kLocating;
    cmd.confidence = 0.0;
    cmd.detail = "case III needs the pose: " + std::move(detail);
    return cmd;
  };
  if (!pose_usable(estimate.mode)) return locating(fmt::format("estimator {}", to_string(estimate.mode)));
  mapping::pose_uncertainty(estimate);  // throws navaid::Error for a broken covariance
  const Mat6 now = pose_cov_W(estimate);
  const Mat6 dcov = config_.scope == HandGuidanceScope::kSinceSeen ? psd_floor(now - remembered_->pose_cov_W) : now;
  const double heading_sigma = std::sqrt(std::max(0.0, dcov(2, 2)));
  const double position_sigma = max_sigma(dcov.bottomRightCorner<3, 3>());
  const char* scope_name = config_.scope == HandGuidanceScope::kSinceSeen ? "gained since seen" : "absolute";
  if (heading_sigma > config_.max_heading_sigma_rad) {
    return locating(fmt::format("heading sigma ({}) {:.1f} deg > {:.1f} deg", scope_name, rad_to_deg(heading_sigma),
                                rad_to_deg(config_.max_heading_sigma_rad)));
  }
  if (position_sigma > config_.max_position_sigma_m) {
    return locating(fmt::format("position sigma ({}) {:.3f} m > {:.3f} m", scope_name, position_sigma,
                                config_.max_position_sigma_m));
  }
  const Mat3 R_W_B = estimate.T_W_B.rotation();
  const Vec3 d_W = remembered_->P_W - estimate.T_W_B.t;
  const Vec3 P_B = R_W_B.transpose() * d_W;
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = R_W_B.transpose() * hat(d_W);
  J.rightCols<3>() = -R_W_B.transpose();
  const Mat3 cov_B = R_W_B.transpose() * remembered_->measurement_cov_W * R_W_B + J * dcov * J.transpose();
  const SE3 T_H_B = T_H_C_ * T_B_C_.inverse();
  const Mat3 R_H_B = T_H_B.rotation();
  const Vec3 P_H = T_H_B * P_B;
  const Mat3 cov_H = R_H_B * cov_B * R_H_B.transpose();
  const double sigma = lateral_sigma(cov_H);
  if (sigma > config_.max_target_sigma_m) {
    return locating(fmt::format("target lateral sigma {:.3f} m > {:.3f} m", sigma, config_.max_target_sigma_m));
  }
  return metric_command(P_H, cov_H, GuidanceReason::kTargetRemembered, "case III (remembered, through the pose)");
}

}  // namespace navaid::planning
