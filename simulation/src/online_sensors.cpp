#include "navaid/simulation/online_sensors.hpp"

#include <cmath>

#include "navaid/simulation/render_cache.hpp"
#include "navaid/simulation/rgbd_noise_model.hpp"
#include "navaid/simulation/sensor_streams.hpp"

namespace navaid::simulation {

namespace {
// A model's configuration with its own stream of the noise seed, as `navaid simulate` seeds it.
template <class ModelConfig>
ModelConfig seeded(ModelConfig c, std::uint64_t seed) {
  c.seed = seed;
  return c;
}
}  // namespace

OnlineSensors::OnlineSensors(const Scenario& scenario, const SimulationConfig& config, const WalkerTrajectory& nominal,
                             const std::optional<CameraCalibration>& render_camera)
    : scenario_(&scenario),
      config_(config),
      world_(scenario.world),
      camera_(make_camera_model(config.camera, "sensor.camera")),
      render_calibration_(render_camera.value_or(config.camera)),
      render_camera_(make_camera_model(render_calibration_, "sensor.camera")),
      renderer_(world_, *render_camera_),
      landmarks_(generate_landmarks(world_, nominal, config.features, scenario.seed)),
      ground_z_m_(nominal.config().ground_z_m),
      observer_(world_, *camera_, landmarks_, config.features),
      feature_rng_(model_seed(config.seed, ModelStream::kFeatures)),
      imu_(config.imu, imu_options(config)),
      confusion_(config.label_confusion),
      gnss_(seeded(config.gps, model_seed(config.seed, ModelStream::kGps)), scenario.origin),
      magnetometer_(seeded(config.mag, model_seed(config.seed, ModelStream::kMag))),
      depth_unit_m_(cache_depth_unit_m(config.render.max_depth)) {
  config_.rgbd_noise.focal_px = render_calibration_.fx;  // disparity noise in the rendered image's pixels
  // The cells the nominal path's seeding points lie in are seeded already.
  const double step = config.features.landmark_spacing_m;
  for (double s = 0; s <= nominal.length(); s += step) {
    const Vec2 xy = nominal.path_point(s);
    seeded_cells_.insert({static_cast<long>(std::floor(xy.x() / kSeedCellM)), static_cast<long>(std::floor(xy.y() / kSeedCellM))});
  }
}

void OnlineSensors::seed_landmarks_around(const Vec2& xy) {
  const long cx = static_cast<long>(std::floor(xy.x() / kSeedCellM)), cy = static_cast<long>(std::floor(xy.y() / kSeedCellM));
  for (long dy = -1; dy <= 1; ++dy) {
    for (long dx = -1; dx <= 1; ++dx) {
      if (!seeded_cells_.insert({cx + dx, cy + dy}).second) continue;
      // The cell's own seed: the same cell gets the same landmarks whichever way the person came.
      std::mt19937_64 rng(scenario_->seed * 1000003ULL + static_cast<std::uint64_t>((cx + dx) * 73856093L ^ (cy + dy) * 19349663L));
      std::normal_distribution<double> normal(0.0, 1.0);
      const Vec3 origin((cx + dx + 0.5) * kSeedCellM, (cy + dy + 0.5) * kSeedCellM, ground_z_m_ + config_.features.seed_height_m);
      seed_landmarks_from(world_, origin, config_.features, rng, normal, landmarks_);
    }
  }
}

OnlineSensors::~OnlineSensors() = default;

ImuSample OnlineSensors::imu(const KinematicState& body, Timestamp t) { return imu_.measure(body, kSimulationEpoch + t); }

FeatureFrame OnlineSensors::features(const SE3& T_W_B, Timestamp t) {
  seed_landmarks_around(T_W_B.t.head<2>());
  const SE3 T_W_C = T_W_B * config_.camera.T_B_C;
  const auto moving = moving_caster(*scenario_, ns_to_seconds(t), T_W_C.t);
  return observer_.observe(camera_stamp(config_, t), T_W_C, feature_rng_, moving ? &*moving : nullptr);
}

std::optional<GpsFix> OnlineSensors::gps(const SE3& T_W_B, Timestamp t) {
  if (!config_.gps_enabled) return std::nullopt;
  const Vec3 antenna = T_W_B * config_.mount.gps_lever_arm_B;
  return gnss_.measure(kSimulationEpoch + t, antenna, SE3::identity(), urban_canyon_factor(world_, antenna));
}

std::optional<MagSample> OnlineSensors::mag(const SE3& T_W_B, Timestamp t) {
  if (!config_.mag_enabled) return std::nullopt;
  return magnetometer_.measure(kSimulationEpoch + t, SE3::identity(), T_W_B);
}

RgbdFrame OnlineSensors::rgbd(const SE3& T_W_B, Timestamp t, std::uint64_t index) {
  const SE3 T_W_C = T_W_B * config_.camera.T_B_C;
  const auto moving = moving_caster(*scenario_, ns_to_seconds(t), T_W_C.t);
  renderer_.render(T_W_C, config_.render, clean_, moving ? &*moving : nullptr);
  clean_.depth = quantize_depth(clean_.depth, depth_unit_m_);
  NoisyRgbd noisy = apply_rgbd_noise(clean_, config_.rgbd_noise, config_.seed, index);
  RgbdFrame f;
  f.t = camera_stamp(config_, t);
  f.index = index;
  f.camera = render_calibration_.name;
  f.depth = std::move(noisy.depth);
  if (config_.render.render_intensity) f.intensity = std::move(noisy.intensity);
  if (!clean_.labels.empty()) {
    LabelPrediction labels = confusion_.apply(clean_.labels, config_.seed, index);
    f.labels = std::move(labels.labels);
    f.label_confidence = std::move(labels.confidence);
  }
  return f;
}

}  // namespace navaid::simulation
