#pragma once
// W-ROMA hand guidance (seed w-roma-rgbd-vio-object-manipulation, Sec. IV): one command per
// camera frame that leads the hand holding the camera to the target object.
//
//   case I   the target is detected in this frame and the depth patch around its centre holds
//            enough valid depth: P_C = median depth along the centre pixel's ray, P_H = T_H_C P_C,
//            the command from the sector rule (hand_sector.hpp). Needs no pose. When the pose is
//            usable the centre is also stored in W for case III.
//   case II  detected, but the patch has too little depth in [depth_min, depth_max] (the object
//            is beyond the depth camera's range): bearing only. Action go, reason kTargetFar
//            ("walk towards it"), the hand command from the bearing (hand_direction_of_bearing)
//            so that the hand stays aligned while walking, and heading_rad = the bearing's
//            direction in the body frame (positive left). target_H is not set (no distance).
//   case III not detected in this frame, but stored earlier: P_H = T_H_C T_C_B T_B_W P_W through
//            the current pose estimate. Needs the pose: with the estimator initializing or lost,
//            or its heading / position sigma (see below) above the limits, the command is wait /
//            kLocating with the reason in `detail`.
//   never seen: wait / kTargetNotSeen.
// Aligned and nearer than reach_distance_m (cases I and III): arrived / kTargetReached, hand kHold.
//
// Uncertainty carried with the remembered position: at storage we keep P_W, the covariance of
// the measurement alone moved into W (pixel sigma along the image axes, depth sigma along the
// ray: Sigma_meas_W = R_W_C J Sigma_{u,v,z} J^T R_W_C^T) and the pose covariance at that time.
// The stored point was placed with the pose estimate of that time, so the pose error it shares
// with the current estimate cancels when it is mapped back into H; what is left is the error the
// estimator gained since (sigma^2(now) - sigma^2(then) for the rotation block moved into W and
// the position block, floored at 0: errors that accumulate as a random walk have independent
// increments, as in the mapping gate's window scope). In case III the target's covariance in H is
//   Sigma_H = R_H_B ( R_W_B^T Sigma_meas_W R_W_B + J_pose dSigma_pose J_pose^T ) R_H_B^T,
// J_pose = d P_B / d(dtheta_W, dp) = [ R_W_B^T [P_W - p]_x , -R_W_B^T ].
// The gates on heading and position sigma use that gained uncertainty by default (scope
// "since-seen"); scope "absolute" gates on the estimate's own sigma instead. A target whose
// lateral sigma in H exceeds max_target_sigma_m is withheld too (the sector could be wrong).
// confidence = 1 - lateral sigma / confidence_sigma_m, clamped to [0, 1].
#include <array>
#include <optional>

#include "navaid/core/camera.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/image.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/guidance_command.hpp"
#include "navaid/planning/hand_sector.hpp"

namespace navaid::planning {

/// What the depth image says in the square patch around the detection's centre.
struct DepthPatchStats {
  int total = 0;           ///< pixels in the patch (inside the image)
  int valid = 0;           ///< pixels with depth in [depth_min, depth_max]
  double median_m = 0.0;   ///< median of the valid depths (0 when none)
  double spread_m = 0.0;   ///< 1.4826 x median absolute deviation of the valid depths
};

/// The patch of half size `half_px` (a (2 half_px + 1)^2 square) around `centre_px` (rounded);
/// depth 0 or non-finite is invalid, as are depths outside [depth_min_m, depth_max_m].
DepthPatchStats depth_patch_stats(const ImageF32& depth, const Eigen::Vector2d& centre_px, int half_px,
                                  double depth_min_m, double depth_max_m);

/// The target object found in this frame (by the AprilTag detector or any other).
struct TargetDetection {
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();  ///< pixel (u, v), core/camera.hpp convention
  std::optional<std::array<Eigen::Vector2d, 4>> corners_px;
  std::optional<DepthPatchStats> depth;
};

/// The target as hand guidance takes it from a tag detection: its centre and corners and, when
/// `depth` is not empty, the depth patch of half size `patch_half_px` around the centre.
TargetDetection target_from_tag(const AprilTagDetection& tag, const ImageF32& depth, int patch_half_px,
                                double depth_min_m, double depth_max_m);

enum class HandGuidanceScope { kSinceSeen, kAbsolute };

struct HandGuidanceConfig {
  HandSectorConfig sector;
  int patch_half_px = 5;                 ///< 11 x 11 patch (Fig. 4b's green square)
  double min_valid_fraction = 0.3;       ///< "a sufficient number of data points"
  double pixel_sigma_px = 1.0;           ///< detection centre noise
  double min_depth_sigma_m = 0.005;      ///< floor on the depth sigma
  double max_heading_sigma_rad = 0.2617993878;  ///< 15 deg: well inside a 45 deg sector
  double max_position_sigma_m = 0.15;    ///< a hand-sized error
  double max_target_sigma_m = 0.25;      ///< lateral sigma of the target in H
  double confidence_sigma_m = 0.25;      ///< confidence falls to 0 at this lateral sigma
  HandGuidanceScope scope = HandGuidanceScope::kSinceSeen;
};

/// Keys planning.hand.*: patch_half_px [0, 50], min_valid_fraction (0, 1], pixel_sigma_px
/// [0, 20], min_depth_sigma_m [0, 1], max_heading_sigma_deg [0.1, 180], max_position_sigma_m
/// [0.001, 100], max_target_sigma_m [0.001, 100], confidence_sigma_m [0.001, 100],
/// scope (since-seen | absolute), plus the sector keys (read_hand_sector_config).
HandGuidanceConfig read_hand_guidance_config(const Config& config);

/// The target as remembered for case III.
struct RememberedTarget {
  Timestamp t = 0;
  Vec3 P_W = Vec3::Zero();
  Mat3 measurement_cov_W = Mat3::Zero();
  Eigen::Matrix<double, 6, 6> pose_cov_W = Eigen::Matrix<double, 6, 6>::Zero();  ///< [dtheta_W, dp] at t
};

class HandGuidance {
 public:
  /// `camera` gives the intrinsics, the depth range (calibration depth_min_m / depth_max_m, or
  /// 0.3-5 m, the Structure Core's, when unset) and T_B_C; T_H_C places the hand.
  HandGuidance(const HandGuidanceConfig& config, const CameraModel& camera, const SE3& T_H_C);

  /// One frame. Throws navaid::Error for a broken covariance when the pose is needed.
  GuidanceCommand update(const StateEstimate& estimate, const std::optional<TargetDetection>& detection);

  const std::optional<RememberedTarget>& remembered() const { return remembered_; }
  void forget() { remembered_.reset(); }

 private:
  HandGuidanceConfig config_;
  const CameraModel& camera_;
  SE3 T_H_C_;
  SE3 T_B_C_;
  double depth_min_m_;
  double depth_max_m_;
  std::optional<RememberedTarget> remembered_;
};

}  // namespace navaid::planning
