#pragma once
// Keyframe decision (VINS-Mono / W-ROMA RGBD-VIO): a frame becomes a keyframe when the features
// it shares with the last keyframe moved on average by at least a parallax threshold, or when too
// few features are shared (tracking is being lost). Parallax is measured in undistorted pixels
// (f times the normalized coordinates) so that lens distortion does not count as motion; with a
// rotation R_cur_kf (from the gyro) the keyframe's points are first rotated into the current view
// (points at infinity move by the infinite homography), so a pure rotation gives no parallax.
#include <cstddef>
#include <optional>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"

namespace navaid::estimation {

struct KeyframeCriteria {
  double min_parallax_px = 10.0;  ///< average parallax that makes a keyframe, > 0
  std::size_t min_tracked = 50;   ///< fewer common tracks than this make a keyframe
};

struct KeyframeDecision {
  bool keyframe = false;
  double average_parallax_px = 0.0;  ///< over the common tracks (0 when there are none)
  std::size_t common_tracks = 0;     ///< tracks seen in both frames (and undistortable)
};

/// `R_cur_kf` rotates directions from the keyframe's camera frame into the current one
/// (d_cur = R_cur_kf d_kf). Features are matched by track_id; both frames' ids must be strictly
/// increasing (FeatureFrame's invariant; std::invalid_argument otherwise).
KeyframeDecision decide_keyframe(const FeatureFrame& last_keyframe, const FeatureFrame& current, const CameraModel& camera,
                                 const KeyframeCriteria& criteria, const std::optional<Eigen::Matrix3d>& R_cur_kf = std::nullopt);

}  // namespace navaid::estimation
