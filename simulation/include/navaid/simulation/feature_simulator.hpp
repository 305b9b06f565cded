#pragma once
// Feature-level simulation (as OpenVINS' simulator does): landmarks on the world's surfaces and,
// per camera frame, their noisy pixel observations (plus depth where the sensor measures it),
// without rendering or image processing. Back-end tests get exact data associations (track id =
// landmark id) with realistic visibility: landmarks are placed where rays from the walked path hit
// geometry, and an observation requires a free line of sight (ray cast, people included).
//
// Track persistence mimics a KLT front end: landmarks seen in the previous frame are kept first,
// then new ones fill empty cells of a grid over the image, up to max_features_per_frame.
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "navaid/core/camera.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::simulation {

struct FeatureSimConfig {
  double landmark_spacing_m = 0.5;   ///< landmark seeding points along the path [m], > 0
  int rays_per_seed_point = 60;      ///< rays cast from each seeding point, >= 1
  double seed_height_m = 1.5;        ///< height of the seeding points above ground
  double max_landmark_distance_m = 12.0;  ///< hits farther from the seeding point are not landmarks
  double max_observation_range_m = 15.0;  ///< landmarks farther from the camera are not observed
  double pixel_sigma_px = 1.0;       ///< white pixel noise per axis, >= 0
  int max_features_per_frame = 150;  ///< >= 1
  int grid_cols = 8, grid_rows = 6;  ///< new tracks go to emptier cells first
  double image_border_px = 5.0;      ///< observations closer to the border are dropped
  /// Disparity noise of the depth measurements [px]; unset: the camera's depth_disparity_sigma_px
  /// (0 = exact depths, while the calibration keeps the sensor's sigma for the estimator).
  std::optional<double> disparity_sigma_px;
};

/// Throws ConfigError naming the first bad key ("features.<name>").
void validate(const FeatureSimConfig& config);

/// Landmarks where rays from seeding points along the walked path hit the world (ids 0, 1, ...).
/// Deterministic for a seed.
std::vector<Landmark> generate_landmarks(const RayCaster& world, const WalkerTrajectory& path,
                                         const FeatureSimConfig& config, std::uint64_t seed);

/// The rays of one seeding point: `rays_per_seed_point` directions (isotropic, flattened towards
/// the horizon) from `origin`; each hit within max_landmark_distance_m becomes a landmark with the
/// next id. generate_landmarks seeds along a path; closed-loop sensors also where the person goes.
void seed_landmarks_from(const RayCaster& world, const Vec3& origin, const FeatureSimConfig& config,
                         std::mt19937_64& rng, std::normal_distribution<double>& normal, std::vector<Landmark>& landmarks);

class FeatureObserver {
 public:
  /// Depth is measured for landmarks within [depth_min_m, depth_max_m] of the camera calibration
  /// when it has a depth section, with the stereo noise sigma_z = z^2 sigma_d / (f b). Keeps
  /// references to world, camera and landmarks: they must outlive the observer.
  FeatureObserver(const RayCaster& world, const CameraModel& camera, const std::vector<Landmark>& landmarks,
                  const FeatureSimConfig& config);

  /// Observations at time t of a camera at T_W_C; `dynamic` (may be null) holds moving obstacles
  /// that also block the view. Call in time order: track persistence depends on the previous call.
  FeatureFrame observe(Timestamp t, const SE3& T_W_C, std::mt19937_64& rng, const RayCaster* dynamic = nullptr);

 private:
  bool visible(const Vec3& origin, const Vec3& p_W, const RayCaster* dynamic) const;

  const RayCaster* world_;
  const CameraModel* camera_;
  const std::vector<Landmark>* landmarks_;
  FeatureSimConfig config_;
  std::vector<std::uint64_t> previous_;  // landmark ids observed in the previous frame (sorted)
};

}  // namespace navaid::simulation
