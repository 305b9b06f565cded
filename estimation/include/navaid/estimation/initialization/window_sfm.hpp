#pragma once
// Vision-only structure from motion over the keyframes of the initialization window (W-ROMA
// RGBD-VIO §V-A; the structure of VINS-Mono's GlobalSFM, with depth):
//
//  1. Reference pair: the oldest keyframe l that shares >= min_common_features tracks with the
//     newest keyframe n at >= min_parallax_px mean parallax, and whose pose change
//     (estimate_pose_change, HPnP or 3D-2D PnP as options.method says) succeeds. A window with no
//     depth at all uses the essential matrix instead (translation of unit length: up to scale).
//  2. Points in frame l: from depth where a keyframe of known pose measured it (P = T_l_Ck Z [m; 1]),
//     otherwise by linear triangulation over every keyframe of known pose that sees the track
//     (rays at least min_triangulation_angle_deg apart, in front of every camera).
//  3. The other keyframes, the one seeing the most known points first: cv::solvePnPRansac on those
//     points, then more points (step 2) with the new pose; repeated until every keyframe has a pose.
//  4. Global bundle adjustment (Ceres) over all keyframe poses and points: reprojection residuals
//     on the normalized plane scaled by focal_px / pixel_sigma_px with a Cauchy loss, and, where
//     depth was measured, an extra residual on the inverse depth (1/Z - 1/Z_meas) / inverse_depth_sigma
//     (W-ROMA's inverse-depth factor; Cauchy too, so that a wrong depth cannot pull the
//     structure). The gauge is the reference keyframe's pose, held constant; without depth the
//     newest keyframe's position is held as well (it fixes the scale).
//
// Output: T_l_C[k] (camera k into the reference camera frame l), the points in l, success or the
// reason of failure. Poses are metric when depth was measured, otherwise up_to_scale is set.
// Points placed before the BA that the triangulating / depth keyframes do not reproject within
// 2 pnp_ransac_threshold_px are left out, as are the reference pose change's outlier tracks;
// points seen by one keyframe only are reported but not adjusted.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/geometry.hpp"
#include "navaid/estimation/initialization/pose_change.hpp"

namespace navaid::estimation {

/// One feature of one keyframe: normalized undistorted coordinates (z = 1) and, when measured,
/// its depth along the optical axis.
struct SfmObservation {
  std::uint64_t track_id = 0;
  Vec2 m = Vec2::Zero();
  std::optional<double> depth_m;
};

/// The features of one keyframe (track ids unique within it).
struct SfmKeyframe {
  std::vector<SfmObservation> observations;
};

struct WindowSfmOptions {
  PoseChangeMethod method = PoseChangeMethod::kHybrid;  ///< step 1, passed to estimate_pose_change
  PoseChangeOptions pose_change;        ///< its options (focal_px is overwritten by focal_px below)
  double focal_px = 460;                ///< converts the pixel thresholds and sigmas, > 0
  int min_common_features = 20;         ///< tracks shared by the reference pair
  double min_parallax_px = 20;          ///< mean parallax of the reference pair [px]
  double min_triangulation_angle_deg = 1.0;
  int min_pnp_points = 8;               ///< known points a keyframe needs for its PnP
  double pnp_ransac_threshold_px = 2.0;
  double pixel_sigma_px = 1.0;          ///< reprojection residual whitening
  double inverse_depth_sigma = 0.02;    ///< [1/m] depth residual whitening (sigma_d / (f b))
  double cauchy_scale = 1.0;            ///< Cauchy loss scale on the whitened residuals
  int max_ba_iterations = 100;
  /// BA result with a larger median reprojection error fails (the median ignores outliers the
  /// Cauchy loss has already discounted).
  double max_median_error_px = 2.0;
};

/// Throws ConfigError naming the first bad option.
void validate(const WindowSfmOptions& options, const std::string& source = "window_sfm");

struct WindowSfm {
  bool success = false;
  std::string failure;          ///< why not, when !success
  std::size_t reference = 0;    ///< index of the reference keyframe l
  bool up_to_scale = false;     ///< no depth in the window: |t_l_n| = 1 before the BA
  std::vector<SE3> T_l_C;       ///< per keyframe: camera k into frame l (identity for l)
  std::map<std::uint64_t, Vec3> points_l;  ///< per track: the point in frame l
  PoseChange reference_pose_change;        ///< step 1's result (T_j_i = T_n_l)
  int depth_residuals = 0;                 ///< inverse-depth residuals in the BA
  int reprojection_residuals = 0;
  double initial_rms_px = 0, final_rms_px = 0;  ///< rms reprojection error [px] before / after the BA
};

/// Runs steps 1-4 on keyframes in time order (>= 2). Degenerate windows (no pair with enough
/// parallax or common tracks, failed pose change, too few points for a PnP, BA failure) return
/// success = false with a reason. Throws Error on malformed input (fewer than 2 keyframes,
/// non-finite coordinates, non-positive or non-finite depth, a track twice in one keyframe) and
/// ConfigError on bad options.
WindowSfm solve_window_sfm(const std::vector<SfmKeyframe>& keyframes, const WindowSfmOptions& options = {});

}  // namespace navaid::estimation
