#pragma once
// Settings of the image front end (feature_tracker.hpp); defaults follow VINS-Mono / W-ROMA
// RGBD-VIO at 640x480, 30 Hz. Pixel quantities are in image pixels of the camera the tracker
// is built for. Details: docs/estimator.md, "Front end".
#include <string>

namespace navaid::estimation {

struct FrontendConfig {
  // Detection (Shi-Tomasi, cv::goodFeaturesToTrack).
  int max_features = 150;          ///< tracks kept per frame, >= 1
  double min_distance_px = 20.0;   ///< minimum distance between features, >= 0
  double quality_level = 0.01;     ///< Shi-Tomasi quality relative to the best corner, in (0, 1)
  int corner_block_size = 3;       ///< structure-tensor window [px], odd, >= 3
  /// Detect only when at least this many tracks are missing from max_features, in [1,
  /// max_features]: the Shi-Tomasi pass costs the same for 2 corners as for 150, so it is batched
  /// (the track count stays within [max_features - this + 1, max_features]). 1 = every frame.
  int detect_min_missing = 10;
  /// No new corners within this distance of a depth discontinuity (occlusion junctions slide as
  /// the view changes); 0 = off, >= 0. Needs the depth image.
  int depth_edge_margin_px = 10;
  double depth_edge_relative_jump = 0.1;  ///< 3x3 depth jump / nearer depth that marks an edge, > 0

  // Pyramidal KLT (cv::calcOpticalFlowPyrLK).
  int klt_window_px = 21;          ///< square search window side, odd, >= 5
  int klt_max_level = 3;           ///< pyramid levels above full resolution (OpenCV maxLevel), in [0, 8]
  int klt_max_iterations = 30;     ///< per level, >= 1
  double klt_epsilon = 0.01;       ///< iteration stop on the update [px], > 0
  bool forward_backward_check = true;
  double fb_threshold_px = 1.0;    ///< |back-tracked - original| limit, > 0
  /// Pyramid levels of the backward pass, in [0, 8]. It starts at the original point, so it needs
  /// no coarse levels to converge (VINS-Fusion uses 1); fewer levels halve its cost.
  int fb_max_level = 1;
  /// Threads a KLT pass splits its points over, in [1, 16]: each point is tracked on its own
  /// window, so the split changes nothing in the result (OpenCV's global parallelism stays off).
  int klt_threads = 2;

  /// Drift check against the track's first appearance: every this many frames of a track's age
  /// (0 = off), its birth patch (klt_window_px + 10 px square, cut at the detected corner) is
  /// KLT-aligned into the frame at full resolution. Frame-to-frame KLT accumulates error with age
  /// (docs/estimator.md, "Front end or back end"); the template does not. 3 (0.1 s at 30 Hz) was
  /// chosen on rendered lab-walk-1 (seeds 1, 2) among 3, 5 and 10 while looking at NEES and ATE.
  int drift_check_interval = 3;
  /// The aligned position replaces the tracked one when within this distance [px]; farther (or
  /// not converging), the track is dropped as drifted. > 0.
  double drift_max_px = 2.0;

  // Outlier rejection.
  bool ransac = true;              ///< fundamental-matrix RANSAC on undistorted points
  double ransac_threshold_px = 1.0;  ///< epipolar distance limit [px], > 0
  double ransac_confidence = 0.99;   ///< in (0, 1)
  double border_px = 1.0;          ///< tracks closer than this to the image edge are dropped, >= 0

  /// Predict KLT's start from the gyro rotation (infinite homography K R K^-1) when a rotation is
  /// passed to FeatureTracker::track().
  bool imu_prediction = true;

  // Depth association (depth_association.hpp).
  int depth_patch_size = 3;                ///< 3 or 5
  double depth_max_relative_spread = 0.1;  ///< (max - min) / median of the patch's valid depths, > 0
  int depth_min_valid = 5;                 ///< valid pixels needed in the patch, in [1, patch^2]

  // Keyframe decision (keyframe_selector.hpp).
  double keyframe_parallax_px = 10.0;  ///< average parallax since the last keyframe, > 0
  int keyframe_min_tracked = 50;       ///< fewer common tracks than this make a keyframe, >= 0
};

/// Throws ConfigError(source, key, ...) naming the first bad key and its allowed range.
void validate(const FrontendConfig& config, const std::string& source = "frontend");

}  // namespace navaid::estimation
