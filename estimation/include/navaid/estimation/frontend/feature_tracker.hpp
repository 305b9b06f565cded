#pragma once
// The image front end: turns RgbdFrames into FeatureFrames (W-ROMA RGBD-VIO §V, VINS-Mono's
// feature tracker). Per frame:
//   1. pyramidal KLT from the previous frame, started at the previous positions or, when a gyro
//      rotation is given, at the infinite-homography prediction K R K^-1 (through the camera's
//      distortion model);
//   2. forward-backward check: tracking back (fb_max_level pyramid levels, from the original
//      point) must land within fb_threshold_px of the start;
//   3. every drift_check_interval frames of a track's age, alignment of its birth patch into the
//      frame (KLT at full resolution): within drift_max_px the track moves there, else it is dropped;
//      then image-border rejection;
//   4. fundamental-matrix RANSAC on undistorted points scaled to pixels (f x + c), so the
//      threshold is an epipolar distance in pixels whatever the lens distortion;
//   5. older tracks win when two survivors come closer than min_distance_px; when at least
//      detect_min_missing tracks are missing, Shi-Tomasi corners fill up to max_features, away
//      (min_distance_px) from the tracks and (depth_edge_margin_px) from depth discontinuities;
//   6. depth from the aligned depth image (depth_association.hpp) within the camera's depth range.
// Output uv are distorted pixels (as detected); track ids are never reused and increase with
// age, so each FeatureFrame is sorted by track id.
//
// Threading: the tracker sets nothing global (no cv::setNumThreads); OpenCV's own parallelism is
// whatever the process configured. Same frames -> same output.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/estimation/frontend/frontend_config.hpp"
#include "navaid/estimation/frontend/keyframe_selector.hpp"

namespace navaid::estimation {

/// What happened in one call of FeatureTracker::track().
struct FrontendStats {
  std::size_t tracked = 0;          ///< tracks continued from the previous frame (after all checks)
  std::size_t new_features = 0;     ///< corners detected in this frame
  std::size_t lost_klt = 0;         ///< KLT did not converge or left the image
  std::size_t rejected_fb = 0;      ///< failed the forward-backward check
  std::size_t drift_checked = 0;    ///< tracks aligned to their birth patch (drift_check_interval)
  std::size_t drift_corrected = 0;  ///< ... and moved there (by more than 0.05 px)
  std::size_t rejected_drift = 0;   ///< ... and dropped: farther than drift_max_px, or no convergence
  std::size_t rejected_border = 0;  ///< within border_px of the edge
  std::size_t rejected_ransac = 0;  ///< fundamental-matrix outliers
  std::size_t pruned_close = 0;     ///< surviving tracks dropped for crowding an older track
  std::size_t with_depth = 0;       ///< output features with an associated depth
  // Wall time per stage [ms].
  double ms_pyramid = 0, ms_klt = 0, ms_ransac = 0, ms_detect = 0, ms_depth = 0, ms_total = 0;
};

class FeatureTracker {
 public:
  /// Validates the config (ConfigError). The depth range is the camera's [depth_min_m,
  /// depth_max_m]; a camera without one (depth_max_m = 0) gets no depths.
  explicit FeatureTracker(std::shared_ptr<const CameraModel> camera, const FrontendConfig& config = {});

  /// Tracks into `frame` (its intensity must be loaded; grey or RGB, the camera's size;
  /// navaid::Error otherwise). `R_cur_prev`: rotation of the camera from the previous frame to
  /// this one, d_cur = R_cur_prev d_prev (e.g. from integrated gyro rates and T_B_C), used for the
  /// KLT prediction when config.imu_prediction is on.
  FeatureFrame track(const RgbdFrame& frame, const std::optional<Eigen::Matrix3d>& R_cur_prev = std::nullopt);

  /// Statistics of the last track() call.
  const FrontendStats& stats() const { return stats_; }
  const FrontendConfig& config() const { return config_; }
  const CameraModel& camera() const { return *camera_; }
  /// Keyframe decision against `last_keyframe` with this config's thresholds.
  KeyframeDecision decide_keyframe(const FeatureFrame& last_keyframe, const FeatureFrame& current,
                                   const std::optional<Eigen::Matrix3d>& R_cur_kf = std::nullopt) const;

  /// Forgets all tracks (the next frame only detects); ids keep increasing.
  void reset();

  /// Fault injection for tests: called with the tracked positions after the forward-backward check
  /// and before the border check and RANSAC; it may move them (not add or remove).
  using TrackHook = std::function<void(const std::vector<std::uint64_t>& ids, std::vector<Eigen::Vector2d>& uv)>;
  void set_track_hook(TrackHook hook) { hook_ = std::move(hook); }

  ~FeatureTracker();
  FeatureTracker(FeatureTracker&&) noexcept;
  FeatureTracker& operator=(FeatureTracker&&) noexcept;
  FeatureTracker(const FeatureTracker&) = delete;
  FeatureTracker& operator=(const FeatureTracker&) = delete;

 private:
  struct State;  // OpenCV pyramids of the previous frame (kept out of this header)

  std::shared_ptr<const CameraModel> camera_;
  FrontendConfig config_;
  std::unique_ptr<State> state_;
  std::vector<std::uint64_t> ids_;      // current tracks, increasing
  std::vector<Eigen::Vector2d> uv_;     // their distorted pixels in the previous frame
  std::vector<int> age_;                // frames each track has been seen
  std::uint64_t next_id_ = 0;
  FrontendStats stats_;
  TrackHook hook_;
};

}  // namespace navaid::estimation
