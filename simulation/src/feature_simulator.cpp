#include "navaid/simulation/feature_simulator.hpp"

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::simulation {

namespace {

void require_features_key(bool ok, const char* key, const char* what) {
  if (!ok) throw ConfigError("", std::string("features.") + key, what);
}

}  // namespace

void validate(const FeatureSimConfig& c) {
  require_features_key(c.landmark_spacing_m > 0 && std::isfinite(c.landmark_spacing_m), "landmark_spacing", "must be > 0");
  require_features_key(c.rays_per_seed_point >= 1, "rays_per_seed_point", "must be >= 1");
  require_features_key(std::isfinite(c.seed_height_m), "seed_height", "must be finite");
  require_features_key(c.max_landmark_distance_m > 0, "max_landmark_distance", "must be > 0");
  require_features_key(c.max_observation_range_m > 0, "max_observation_range", "must be > 0");
  require_features_key(c.pixel_sigma_px >= 0 && std::isfinite(c.pixel_sigma_px), "pixel_sigma", "must be >= 0");
  require_features_key(c.max_features_per_frame >= 1, "max_per_frame", "must be >= 1");
  require_features_key(c.grid_cols >= 1 && c.grid_rows >= 1, "grid", "needs >= 1 column and row");
  require_features_key(c.image_border_px >= 0, "image_border", "must be >= 0");
  require_features_key(!c.disparity_sigma_px || (*c.disparity_sigma_px >= 0 && std::isfinite(*c.disparity_sigma_px)),
          "disparity_sigma", "must be >= 0");
}

std::vector<Landmark> generate_landmarks(const RayCaster& world, const WalkerTrajectory& path,
                                         const FeatureSimConfig& config, std::uint64_t seed) {
  validate(config);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Landmark> landmarks;
  const double ground = path.config().ground_z_m;
  const int n = static_cast<int>(std::floor(path.length() / config.landmark_spacing_m)) + 1;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d xy = path.path_point(std::min(k * config.landmark_spacing_m, path.length()));
    seed_landmarks_from(world, Vec3(xy.x(), xy.y(), ground + config.seed_height_m), config, rng, normal, landmarks);
  }
  return landmarks;
}

void seed_landmarks_from(const RayCaster& world, const Vec3& origin, const FeatureSimConfig& config,
                         std::mt19937_64& rng, std::normal_distribution<double>& normal, std::vector<Landmark>& landmarks) {
  for (int r = 0; r < config.rays_per_seed_point; ++r) {
    // Isotropic directions, flattened towards the horizon where cameras look.
    Vec3 dir = draw_vector<3>([&] { return normal(rng); });
    dir.z() *= 0.6;
    if (dir.norm() < 1e-9) continue;
    dir.normalize();
    const auto hit = world.cast(origin, dir, config.max_landmark_distance_m);
    if (!hit) continue;
    landmarks.push_back(Landmark{landmarks.size(), hit->point + 1e-6 * hit->normal});
  }
}

FeatureObserver::FeatureObserver(const RayCaster& world, const CameraModel& camera, const std::vector<Landmark>& landmarks,
                                 const FeatureSimConfig& config)
    : world_(&world), camera_(&camera), landmarks_(&landmarks), config_(config) {
  validate(config_);
}

bool FeatureObserver::visible(const Vec3& origin, const Vec3& p_W, const RayCaster* dynamic) const {
  const Vec3 d = p_W - origin;
  const double range = d.norm();
  const Vec3 dir = d / range;
  const double t_max = range - 1e-3;  // the landmark sits 1 um off its surface
  if (world_->cast(origin, dir, t_max)) return false;
  return !(dynamic && dynamic->cast(origin, dir, t_max));
}

FeatureFrame FeatureObserver::observe(Timestamp t, const SE3& T_W_C, std::mt19937_64& rng, const RayCaster* dynamic) {
  struct Candidate {
    std::uint64_t id;
    const Vec3* p_W;
    Vec3 p_C;
    bool tracked;
  };
  const SE3 T_C_W = T_W_C.inverse();
  const Vec3 origin = T_W_C.t;
  const double range2 = config_.max_observation_range_m * config_.max_observation_range_m;
  std::vector<Candidate> candidates;
  for (const Landmark& l : *landmarks_) {
    if ((l.p_W - origin).squaredNorm() > range2) continue;
    const Vec3 p_C = T_C_W * l.p_W;
    const auto uv = camera_->project(p_C);
    if (!uv || !camera_->in_image(*uv, config_.image_border_px)) continue;
    const bool tracked = std::binary_search(previous_.begin(), previous_.end(), l.id);
    candidates.push_back({l.id, &l.p_W, p_C, tracked});
  }
  // Tracked first, then new ones in a fixed pseudo-random order (no bias towards low ids).
  std::shuffle(candidates.begin(), candidates.end(), rng);
  std::stable_partition(candidates.begin(), candidates.end(), [](const Candidate& c) { return c.tracked; });

  const auto& calib = camera_->calibration();
  const bool has_depth = calib.depth_max_m > 0 && calib.depth_baseline_m > 0;
  const double fb = calib.fx * calib.depth_baseline_m;
  const double sigma_d = config_.disparity_sigma_px.value_or(calib.depth_disparity_sigma_px);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int cells = config_.grid_cols * config_.grid_rows;
  std::vector<int> cell_count(static_cast<std::size_t>(cells), 0);
  const int per_cell = std::max(1, (config_.max_features_per_frame + cells - 1) / cells);
  auto cell_of = [&](const Eigen::Vector2d& uv) {
    const int cx = std::clamp(static_cast<int>(uv.x() * config_.grid_cols / calib.width), 0, config_.grid_cols - 1);
    const int cy = std::clamp(static_cast<int>(uv.y() * config_.grid_rows / calib.height), 0, config_.grid_rows - 1);
    return static_cast<std::size_t>(cy * config_.grid_cols + cx);
  };

  FeatureFrame frame;
  frame.t = t;
  frame.camera = calib.name;
  enum : char { kUntried, kDone };
  std::vector<char> state(candidates.size(), kUntried);
  for (int pass = 0; pass < 2; ++pass) {  // pass 0 respects the per-cell quota for new tracks
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const Candidate& c = candidates[i];
      if (static_cast<int>(frame.features.size()) >= config_.max_features_per_frame) break;
      if (state[i] == kDone) continue;
      const auto uv_true = camera_->project(c.p_C);
      const std::size_t cell = cell_of(*uv_true);
      if (pass == 0 && !c.tracked && cell_count[cell] >= per_cell) continue;
      state[i] = kDone;
      if (!visible(origin, *c.p_W, dynamic)) continue;
      FeatureObservation obs;
      obs.track_id = c.id;
      obs.uv = *uv_true + config_.pixel_sigma_px * draw_vector<2>([&] { return normal(rng); });
      if (!camera_->in_image(obs.uv)) continue;
      const double z = c.p_C.z();
      if (has_depth && z >= calib.depth_min_m && z <= calib.depth_max_m) {
        const double disparity = fb / z + sigma_d * normal(rng);
        if (disparity > 0) obs.depth_m = fb / disparity;
      }
      ++cell_count[cell];
      frame.features.push_back(obs);
    }
  }
  std::sort(frame.features.begin(), frame.features.end(),
            [](const FeatureObservation& a, const FeatureObservation& b) { return a.track_id < b.track_id; });
  previous_.clear();
  for (const auto& f : frame.features) previous_.push_back(f.track_id);
  return frame;
}

}  // namespace navaid::simulation
