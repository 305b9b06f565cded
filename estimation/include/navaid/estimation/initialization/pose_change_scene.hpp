#pragma once
// Synthetic two-view scenes with a known T_j_i for checking and benchmarking pose-change
// estimation (tests, bench/pose_change.cpp): random points in front of camera i, projected into
// both frames with Gaussian pixel noise, a chosen number of them with (noisy) depth, and optional
// gross outliers. Deterministic by seed.
#include <cstdint>
#include <vector>

#include "navaid/estimation/initialization/pose_change.hpp"

namespace navaid::estimation {

struct TwoViewSceneOptions {
  int points = 150;
  double min_depth_m = 1.0;      ///< depth Z_i of the points, uniform in [min, max]
  double max_depth_m = 8.0;
  double half_fov = 0.6;         ///< |x|, |y| <= half_fov on the normalized plane of both frames
  double focal_px = 460;         ///< to express the pixel noise
  double pixel_noise_px = 0.3;   ///< sigma of each image coordinate, both frames
  int depth_features = -1;       ///< features with depth (the first ones; -1: all)
  double depth_noise_rel = 0.0;  ///< sigma of the depth as a fraction of it
  double outlier_fraction = 0.0; ///< features whose m_j is replaced by a random image point
  std::uint64_t seed = 1;
};

struct TwoViewScene {
  SE3 T_j_i;
  std::vector<PoseChangeCorrespondence> correspondences;
  std::vector<char> outlier;  ///< per correspondence
};

/// Throws navaid::Error when the options are unusable (no point visible in both frames).
TwoViewScene make_two_view_scene(const SE3& T_j_i, const TwoViewSceneOptions& options);

}  // namespace navaid::estimation
