#include "navaid/simulation/simulation_config.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/config_schema.hpp"

namespace navaid::simulation {

namespace {

std::vector<double> items(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
std::vector<double> items(const Mat3& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

Vec3 get_vec3(const Config& c, const ConfigKey<std::vector<double>>& key) {
  const auto v = get(c, key);
  return Vec3(v[0], v[1], v[2]);
}

// A 3x3 matrix given row by row as 9 numbers.
Mat3 get_mat3(const Config& c, const ConfigKey<std::vector<double>>& key) {
  const auto v = get(c, key);
  Mat3 m;
  m << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
  return m;
}

const SimulationConfig kDefaults;
const RgbdNoiseConfig kRgbd;
const LabelConfusionConfig kLabels;
const GnssModelConfig kGps;
const FeatureSimConfig kFeatures;
const WalkerConfig kWalker;

const ConfigKey<bool> kNoise{"sensor.noise", true, "false switches every sensor's noise off"};

// Scenario and run.
const ConfigKey<long long> kWorldSeed{"simulation.world_seed", 0, 0, std::numeric_limits<long long>::max(),
                                      "seed of the world (layout jitter, people); 0: the scenario's documented seed"};
const ConfigKey<bool> kPeople{"simulation.people", ScenarioOptions{}.people, "moving people"};
const ConfigKey<bool> kVehicles{"simulation.vehicles", ScenarioOptions{}.vehicles, "moving vehicles"};
const ConfigKey<bool> kTargets{"simulation.targets", ScenarioOptions{}.targets,
                               "target objects for hand guidance (the lab walks' tagged box)"};
const ConfigKey<std::string> kLayout{"simulation.layout", std::string("default"), {"default", "random"},
                                     "random: the obstacle layout drawn from the world seed (corridor, "
                                     "obstacle-course)"};
const ConfigKey<double> kMountPitch{"mount_pitch_deg", std::nullopt, {-60.0, 60.0},
                                    "the camera's downward pitch on its mount [deg]; default: the mount's"};
const ConfigKey<long long> kSeed{"seed", 0, 0, std::numeric_limits<long long>::max(),
                                 "noise seed (the rendering does not depend on it)"};
const ConfigKey<double> kDuration{"duration", 0.0, {0, 1e6}, "simulated time [s]; 0: the whole walk"};
const ConfigKey<double> kStillTime{"simulation.still_time", kDefaults.still_time_s, {0, 60},
                                   "standing still before walking off [s]"};
const ConfigKey<int> kLaps{"simulation.laps", kDefaults.laps, 1, 10000, "times round a closed path"};
const ConfigKey<std::string> kMode{"simulation.mode", std::string("images"), {"images", "features"},
                                   "render RGB-D images or simulate feature tracks"};

// Walker.
const ConfigKey<double> kWalkerSpeed{"walker.speed", kWalker.speed_mps, {0.2, 3}, "cruise walking speed [m/s]"};
const ConfigKey<double> kStepFrequency{"walker.step_frequency", kWalker.step_frequency_hz, {0.5, 4},
                                       "steps per second (vertical bob frequency) [Hz]"};
const ConfigKey<double> kBob{"walker.bob_amplitude", kWalker.bob_amplitude_m, {0, 0.2}, "vertical bob amplitude [m]"};
const ConfigKey<double> kSway{"walker.sway_amplitude", kWalker.sway_amplitude_m, {0, 0.2},
                              "lateral sway amplitude [m]"};
const ConfigKey<double> kScanAmplitude{"walker.scan_amplitude", std::nullopt, {0, 1.5},
                                       "yaw scanning amplitude [rad]; default: the mount's"};
const ConfigKey<double> kScanPeriod{"walker.scan_period", std::nullopt, {0.2, 60},
                                    "yaw scanning period [s]; default: the mount's"};

// Camera and depth.
const ConfigKey<std::vector<double>> kResolution{"sensor.camera.resolution", std::nullopt, 2, {16, 4096},
                                                 "[width, height] of the camera (same aspect ratio); default: the "
                                                 "sensor preset's"};
const ConfigKey<double> kCameraRate{"sensor.camera.rate", std::nullopt, {1, 120},
                                    "camera frame rate [Hz]; default: the sensor preset's"};
const ConfigKey<double> kDepthMin{"sensor.depth.min", std::nullopt, {0.05, 20},
                                  "nearest measured depth [m]; default: the sensor preset's"};
const ConfigKey<double> kDepthMax{"sensor.depth.max", std::nullopt, {0.05, 60},
                                  "farthest measured depth [m] (>= sensor.depth.min); default: the sensor preset's"};
const ConfigKey<double> kDepthBaseline{"sensor.depth.baseline", std::nullopt, {1e-3, 1},
                                       "stereo baseline of the depth noise [m]; default: the sensor preset's"};
const ConfigKey<double> kDisparitySigma{"sensor.depth.disparity_sigma", std::nullopt, {0, 5},
                                        "disparity noise sigma [px]; default: the sensor preset's"};
const ConfigKey<double> kTimeOffset{"sensor.camera.time_offset", 0.0, {-0.1, 0.1},
                                    "true camera-IMU time offset [s] (t_imu = t_cam + offset)"};
const ConfigKey<double> kTimeOffsetCalibrated{"sensor.camera.time_offset_calibrated", std::nullopt, {-0.1, 0.1},
                                              "the offset calibration.yaml states [s]; default: the true one"};
const ConfigKey<bool> kDepthNoise{"sensor.depth.noise", kRgbd.depth_noise, "disparity noise and quantization"};
const ConfigKey<double> kDisparityQuantization{"sensor.depth.disparity_quantization", kRgbd.disparity_quantization_px,
                                               {0, 1}, "disparity quantization step [px], e.g. 0.125; 0 = continuous"};
const ConfigKey<double> kEdgeRelativeJump{"sensor.depth.edge_relative_jump", kRgbd.edge_relative_jump, {1e-3, 10},
                                          "3x3 relative depth jump that marks an edge"};
const ConfigKey<double> kEdgeDropout{"sensor.depth.edge_dropout", kRgbd.edge_dropout_probability, {0, 1},
                                     "probability that an edge pixel is invalid"};
const ConfigKey<double> kFlyingPixels{"sensor.depth.flying_pixels", kRgbd.flying_pixel_probability, {0, 1},
                                      "probability that a surviving edge pixel mixes foreground and background"};
const ConfigKey<double> kDepthDropout{"sensor.depth.dropout", kRgbd.dropout_probability, {0, 1},
                                      "probability that any valid depth pixel is invalid"};
const ConfigKey<bool> kIntensityNoise{"sensor.intensity.noise", kRgbd.intensity_noise, "image read and shot noise"};
const ConfigKey<double> kIntensitySigma{"sensor.intensity.sigma", kRgbd.intensity_sigma, {0, 50},
                                        "image read noise sigma [grey levels]"};
const ConfigKey<double> kIntensityShotGain{"sensor.intensity.shot_gain", kRgbd.intensity_shot_gain, {0, 10},
                                           "image shot-noise gain g (variance g I) [grey levels]"};

// Semantic labels.
const ConfigKey<bool> kLabelsNoise{"sensor.labels.noise", kLabels.noise,
                                   "segmentation errors (false: predicted labels are the truth)"};
const ConfigMapKey kLabelsAccuracy{"sensor.labels.accuracy", "accuracy in [0.001, 1] per semantic class name",
                                   "a class's segmentation accuracy (classes not given keep their default)"};
const ConfigKey<int> kCellSize{"sensor.labels.cell_size", kLabels.cell_size_px, 1, 4096,
                               "side of the segmentation error cells [px]"};
const ConfigKey<int> kBoundaryWidth{"sensor.labels.boundary_width", kLabels.boundary_width_px, 0, 16,
                                    "boundary erosion width [px]; 0: off"};
const ConfigKey<double> kBoundaryProbability{"sensor.labels.boundary_probability", kLabels.boundary_probability, {0, 1},
                                             "probability of a boundary pixel's erosion; 0: off"};
const ConfigKey<double> kConfidenceConcentration{"sensor.labels.confidence_concentration",
                                                 kLabels.confidence_concentration, {1e-3, 1e4},
                                                 "kappa of the label confidence; smaller: more spread"};

// IMU.
const ConfigKey<double> kImuRate{"sensor.imu.rate", std::nullopt, {50, 2000}, "IMU rate [Hz]; default: the sensor "
                                                                               "preset's"};
const ConfigKey<double> kGyroNoise{"sensor.imu.gyro_noise_density", std::nullopt, {0, 1},
                                   "gyro white noise density [rad/s/sqrt(Hz)]; default: the sensor preset's"};
const ConfigKey<double> kGyroWalk{"sensor.imu.gyro_random_walk", std::nullopt, {0, 1},
                                  "gyro bias random walk [rad/s^2/sqrt(Hz)]; default: the sensor preset's"};
const ConfigKey<double> kAccelNoise{"sensor.imu.accel_noise_density", std::nullopt, {0, 10},
                                    "accelerometer white noise density [m/s^2/sqrt(Hz)]; default: the sensor preset's"};
const ConfigKey<double> kAccelWalk{"sensor.imu.accel_random_walk", std::nullopt, {0, 10},
                                   "accelerometer bias random walk [m/s^3/sqrt(Hz)]; default: the sensor preset's"};
const ConfigKey<bool> kImuNoise{"sensor.imu.noise", true, "IMU white noise and bias walk"};
const ConfigKey<std::vector<double>> kInitialGyroBias{"sensor.imu.initial_gyro_bias", items(Vec3::Zero().eval()), 3,
                                                      {-1, 1}, "gyro bias at the start [rad/s]"};
const ConfigKey<std::vector<double>> kInitialAccelBias{"sensor.imu.initial_accel_bias", items(Vec3::Zero().eval()), 3,
                                                       {-5, 5}, "accelerometer bias at the start [m/s^2]"};
const ConfigKey<std::vector<double>> kGyroMisalignment{"sensor.imu.gyro_scale_misalignment",
                                                       items(Mat3::Identity().eval()), 9, {-10, 10},
                                                       "gyro scale and misalignment matrix, row by row"};
const ConfigKey<std::vector<double>> kAccelMisalignment{"sensor.imu.accel_scale_misalignment",
                                                        items(Mat3::Identity().eval()), 9, {-10, 10},
                                                        "accelerometer scale and misalignment matrix, row by row"};
const ConfigKey<std::vector<double>> kShocks{"sensor.imu.shocks", std::nullopt, 0, {-1e6, 1e6},
                                             "IMU shocks as groups [start_s, duration_s, ax, ay, az, ...] (seconds "
                                             "since the walk starts, m/s^2); absent: none"};

// GNSS.
const ConfigKey<bool> kGpsEnabled{"sensor.gps.enabled", std::nullopt,
                                  "simulate GNSS fixes; default: on outdoors (route1, route2, school)"};
const ConfigKey<double> kGpsRate{"sensor.gps.rate", kGps.rate_hz, {1, 10}, "GNSS fix rate [Hz]"};
const ConfigKey<double> kGpsSigmaHorizontal{"sensor.gps.sigma_horizontal", kGps.sigma_horizontal_m, {0, 100},
                                            "white-noise sigma per horizontal axis [m]"};
const ConfigKey<double> kGpsSigmaVertical{"sensor.gps.sigma_vertical", kGps.sigma_vertical_m, {0, 100},
                                          "white-noise sigma on up [m]"};
const ConfigKey<bool> kGpsMultipath{"sensor.gps.multipath", true, "Gauss-Markov multipath errors"};
const ConfigKey<double> kGpsMultipathTau{"sensor.gps.multipath_tau", kGps.multipath_tau_s, {0.1, 3600},
                                         "multipath correlation time [s]"};
const ConfigKey<double> kGpsMultipathHorizontal{"sensor.gps.multipath_sigma_horizontal", kGps.multipath_sigma_horizontal_m,
                                                {0, 100}, "open-sky multipath sigma per horizontal axis [m]"};
const ConfigKey<double> kGpsMultipathVertical{"sensor.gps.multipath_sigma_vertical", kGps.multipath_sigma_vertical_m,
                                              {0, 100}, "open-sky multipath sigma on up [m]"};
const ConfigKey<double> kGpsCanyonGain{"sensor.gps.canyon_gain", kGps.canyon_gain, {0, 100},
                                       "k in sigma_mp (1 + k f) of the urban canyon factor f"};
const ConfigKey<bool> kGpsNoise{"sensor.gps.noise", true, "GNSS noise (false: fixes at the truth)"};
const ConfigKey<std::vector<double>> kGpsOutages{"sensor.gps.outages", std::nullopt, 0, {-60, 1e6},
                                                 "GNSS outages as pairs [start, end, ...] in seconds since the walk "
                                                 "starts; absent: none"};
const ConfigKey<double> kGpsOutageCanyon{"sensor.gps.outage_canyon_factor", std::nullopt, {0, 1},
                                         "no fix while the canyon factor is at least this; absent: never"};

// Magnetometer.
const ConfigKey<bool> kMagEnabled{"sensor.mag.enabled", true, "simulate the magnetometer"};
const ConfigKey<double> kMagRate{"sensor.mag.rate", kDefaults.mag_rate_hz, {1, 1000}, "magnetometer rate [Hz]"};
const ConfigKey<double> kMagSigma{"sensor.mag.sigma", kDefaults.mag.sigma_t, {0, 1e-4},
                                  "magnetometer white noise per axis [T]"};
const ConfigKey<std::vector<double>> kMagHardIron{"sensor.mag.hard_iron", items(kDefaults.mag.hard_iron_t), 3,
                                                  {-1e-3, 1e-3}, "magnetometer hard-iron offset [T]"};
const ConfigKey<std::vector<double>> kMagSoftIron{"sensor.mag.soft_iron", items(kDefaults.mag.soft_iron), 9, {-10, 10},
                                                  "magnetometer soft-iron matrix, row by row"};
const ConfigKey<bool> kMagNoise{"sensor.mag.noise", true, "magnetometer noise"};

// Feature-level mode.
const ConfigKey<double> kLandmarkSpacing{"features.landmark_spacing", kFeatures.landmark_spacing_m, {0.05, 100},
                                         "landmark seeding points along the path [m]"};
const ConfigKey<int> kRaysPerSeed{"features.rays_per_seed_point", kFeatures.rays_per_seed_point, 1, 10000,
                                  "rays cast from each seeding point"};
const ConfigKey<double> kMaxObservationRange{"features.max_observation_range", kFeatures.max_observation_range_m,
                                             {0.5, 200}, "landmarks farther from the camera are not observed [m]"};
const ConfigKey<double> kFeaturePixelSigma{"features.pixel_sigma", kFeatures.pixel_sigma_px, {0, 20},
                                           "white pixel noise per axis of feature observations [px]"};
const ConfigKey<int> kMaxPerFrame{"features.max_per_frame", kFeatures.max_features_per_frame, 1, 5000,
                                  "feature observations per frame at most"};

// Keys whose allowed names come from other files: built on first use.
const ConfigKey<std::string>& scenario_key() {
  static const ConfigKey<std::string> key{"scenario", std::nullopt, scenario_names(),
                                          "the scenario to simulate (docs/scenarios.md)"};
  return key;
}
const ConfigKey<std::string>& mount_key() {
  static const ConfigKey<std::string> key{"mount", std::nullopt, mount_names(),
                                          "where the sensor rig is worn; default: the scenario's"};
  return key;
}
const ConfigKey<std::string>& sensor_preset_key() {
  static const ConfigKey<std::string> key{"sensor.preset", std::nullopt, sensor_preset_names(),
                                          "the RGB-D + IMU sensor; default: the mount's"};
  return key;
}

void read_camera(const Config& c, SimulationConfig& s, const SensorPreset& preset) {
  CameraCalibration cam = preset.camera;
  if (c.has(kResolution.name)) {
    const auto res = get(c, kResolution);
    cam = rescale_camera(cam, static_cast<int>(res[0]), static_cast<int>(res[1]));
  }
  cam.rate_hz = get(c, defaulting_to(kCameraRate, cam.rate_hz));
  cam.depth_min_m = get(c, defaulting_to(kDepthMin, cam.depth_min_m));
  cam.depth_max_m = get(c, within(defaulting_to(kDepthMax, cam.depth_max_m), {cam.depth_min_m, 60}));
  cam.depth_baseline_m = get(c, defaulting_to(kDepthBaseline, cam.depth_baseline_m));
  cam.depth_disparity_sigma_px = get(c, defaulting_to(kDisparitySigma, cam.depth_disparity_sigma_px));
  cam.T_B_C = s.mount.T_B_C();
  // A real rig's clocks disagree by milliseconds; 0.1 s bounds what an estimator can still find.
  s.camera_time_offset_s = get(c, kTimeOffset);
  cam.time_offset_s = get(c, defaulting_to(kTimeOffsetCalibrated, s.camera_time_offset_s));
  s.camera = cam;

  RgbdNoiseConfig& n = s.rgbd_noise;
  n = rgbd_noise_config(cam);
  n.noise = get(c, kNoise);
  n.depth_noise = get(c, kDepthNoise);
  n.disparity_quantization_px = get(c, kDisparityQuantization);
  n.edge_relative_jump = get(c, kEdgeRelativeJump);
  n.edge_dropout_probability = get(c, kEdgeDropout);
  n.flying_pixel_probability = get(c, kFlyingPixels);
  n.dropout_probability = get(c, kDepthDropout);
  n.intensity_noise = get(c, kIntensityNoise);
  n.intensity_sigma = get(c, kIntensitySigma);
  n.intensity_shot_gain = get(c, kIntensityShotGain);
  validate(n, "sensor.depth");

  // Rendered a little beyond the sensor's range so that noise can carry a depth across the limit.
  s.render.min_depth = 0.5 * cam.depth_min_m;
  s.render.max_depth = 1.2 * cam.depth_max_m;
}

void read_labels(const Config& c, SimulationConfig& s) {
  LabelConfusionConfig& l = s.label_confusion;
  l.noise = get(c, kNoise) && get(c, kLabelsNoise);
  for (const auto& name : c.child_keys(kLabelsAccuracy.name)) {
    const SemanticClass cls = semantic_class_from_name(name);
    l.accuracy[static_cast<std::size_t>(cls)] = c.get_double(kLabelsAccuracy.name + "." + name, {1e-3, 1});
  }
  l.cell_size_px = get(c, kCellSize);
  l.boundary_width_px = get(c, kBoundaryWidth);
  l.boundary_probability = get(c, kBoundaryProbability);
  l.confidence_concentration = get(c, kConfidenceConcentration);
  validate(l, "sensor.labels");
}

void read_imu(const Config& c, SimulationConfig& s, const SensorPreset& preset) {
  ImuCalibration imu = preset.imu;
  imu.rate_hz = get(c, defaulting_to(kImuRate, imu.rate_hz));
  imu.gyro_noise_density = get(c, defaulting_to(kGyroNoise, imu.gyro_noise_density));
  imu.gyro_random_walk = get(c, defaulting_to(kGyroWalk, imu.gyro_random_walk));
  imu.accel_noise_density = get(c, defaulting_to(kAccelNoise, imu.accel_noise_density));
  imu.accel_random_walk = get(c, defaulting_to(kAccelWalk, imu.accel_random_walk));
  s.imu = imu;
  const bool noise = get(c, kNoise) && get(c, kImuNoise);
  s.imu_options.white_noise = noise;
  s.imu_options.bias_walk = noise;
  s.imu_options.initial_gyro_bias = get_vec3(c, kInitialGyroBias);
  s.imu_options.initial_accel_bias = get_vec3(c, kInitialAccelBias);
  s.imu_options.gyro_scale_misalignment = get_mat3(c, kGyroMisalignment);
  s.imu_options.accel_scale_misalignment = get_mat3(c, kAccelMisalignment);
  if (c.has(kShocks.name)) {  // [start, duration, ax, ay, az, ...]: seconds since the walk starts, m/s^2
    const auto v = get(c, kShocks);
    if (v.size() % 5 != 0)
      throw ConfigError(c.origin("sensor.imu.shocks"), "sensor.imu.shocks",
                        "needs groups [start_s, duration_s, ax, ay, az, ...]");
    for (std::size_t i = 0; i < v.size(); i += 5) {
      if (!(v[i + 1] > 0))
        throw ConfigError(c.origin("sensor.imu.shocks"), "sensor.imu.shocks", "a shock's duration must be > 0 s");
      s.imu_options.shocks.push_back({kSimulationEpoch + seconds_to_ns(v[i]), kSimulationEpoch + seconds_to_ns(v[i] + v[i + 1]),
                                      Vec3(v[i + 2], v[i + 3], v[i + 4])});
    }
  }
}

void read_gps(const Config& c, SimulationConfig& s, const Scenario& scenario) {
  // GNSS is on by default outdoors only: indoors a receiver has no fix worth simulating.
  const bool outdoor = scenario.name == "route1" || scenario.name == "route2" || scenario.name == "school";
  s.gps_enabled = get(c, defaulting_to(kGpsEnabled, outdoor));
  GnssModelConfig& g = s.gps;
  g.rate_hz = get(c, kGpsRate);
  g.sigma_horizontal_m = get(c, kGpsSigmaHorizontal);
  g.sigma_vertical_m = get(c, kGpsSigmaVertical);
  const bool multipath = get(c, kGpsMultipath);
  g.multipath_tau_s = get(c, kGpsMultipathTau);
  g.multipath_sigma_horizontal_m = multipath ? get(c, kGpsMultipathHorizontal) : 0.0;
  g.multipath_sigma_vertical_m = multipath ? get(c, kGpsMultipathVertical) : 0.0;
  g.canyon_gain = get(c, kGpsCanyonGain);
  g.noise = get(c, kNoise) && get(c, kGpsNoise);
  if (c.has(kGpsOutages.name)) {  // [start, end, start, end, ...] seconds since the walk starts
    const auto v = get(c, kGpsOutages);
    if (v.size() % 2 != 0)
      throw ConfigError(c.origin("sensor.gps.outages"), "sensor.gps.outages", "needs pairs [start, end, ...] in seconds");
    for (std::size_t i = 0; i < v.size(); i += 2)
      g.outages.push_back({kSimulationEpoch + seconds_to_ns(v[i]), kSimulationEpoch + seconds_to_ns(v[i + 1])});
  }
  if (c.has(kGpsOutageCanyon.name)) g.outage_canyon_factor = get(c, kGpsOutageCanyon);
  validate(g, "sensor.gps");
}

void read_mag(const Config& c, SimulationConfig& s) {
  s.mag_enabled = get(c, kMagEnabled);
  s.mag_rate_hz = get(c, kMagRate);
  s.mag.sigma_t = get(c, kMagSigma);
  s.mag.hard_iron_t = get_vec3(c, kMagHardIron);
  s.mag.soft_iron = get_mat3(c, kMagSoftIron);
  s.mag.noise = get(c, kNoise) && get(c, kMagNoise);
  validate(s.mag, "sensor.mag");
}

void read_features(const Config& c, SimulationConfig& s) {
  FeatureSimConfig& f = s.features;
  f.landmark_spacing_m = get(c, kLandmarkSpacing);
  f.rays_per_seed_point = get(c, kRaysPerSeed);
  f.max_observation_range_m = get(c, kMaxObservationRange);
  f.pixel_sigma_px = get(c, kFeaturePixelSigma);
  if (!get(c, kNoise)) f.pixel_sigma_px = 0.0;
  // Same switches as the image mode's depth noise; the calibration keeps the sensor's sigma.
  if (!s.rgbd_noise.noise || !s.rgbd_noise.depth_noise) f.disparity_sigma_px = 0.0;
  f.max_features_per_frame = get(c, kMaxPerFrame);
  validate(f);
}

}  // namespace

CameraCalibration rescale_camera(const CameraCalibration& camera, int width, int height) {
  const double sx = static_cast<double>(width) / camera.width, sy = static_cast<double>(height) / camera.height;
  if (std::abs(sx - sy) > 1e-9)
    throw ConfigError("", "sensor.camera.resolution",
                      fmt::format("{}x{} changes the aspect ratio of the {}x{} camera", width, height, camera.width, camera.height));
  CameraCalibration c = camera;
  c.width = width;
  c.height = height;
  c.fx *= sx;
  c.fy *= sy;
  c.cx = (camera.cx + 0.5) * sx - 0.5;
  c.cy = (camera.cy + 0.5) * sy - 0.5;
  return c;
}

const ConfigKey<long long>& world_seed_key() { return kWorldSeed; }

ConfigSchema scenario_options_schema() {
  return ConfigSchema().add(kWorldSeed).add(kPeople).add(kVehicles).add(kTargets).add(kLayout);
}

ConfigSchema simulation_config_schema() {
  ConfigSchema s;
  s.add(scenario_key());
  s.add(scenario_options_schema());
  s.add(mount_key()).add(kMountPitch).add(sensor_preset_key()).add(kSeed).add(kDuration).add(kStillTime).add(kLaps);
  s.add(kMode);
  for (const auto* k : {&kWalkerSpeed, &kStepFrequency, &kBob, &kSway, &kScanAmplitude, &kScanPeriod}) s.add(*k);
  s.add(kResolution);
  for (const auto* k : {&kCameraRate, &kDepthMin, &kDepthMax, &kDepthBaseline, &kDisparitySigma, &kTimeOffset,
                        &kTimeOffsetCalibrated})
    s.add(*k);
  s.add(kNoise).add(kDepthNoise);
  for (const auto* k : {&kDisparityQuantization, &kEdgeRelativeJump, &kEdgeDropout, &kFlyingPixels, &kDepthDropout})
    s.add(*k);
  s.add(kIntensityNoise).add(kIntensitySigma).add(kIntensityShotGain);
  s.add(kLabelsNoise).add(kLabelsAccuracy).add(kCellSize).add(kBoundaryWidth).add(kBoundaryProbability);
  s.add(kConfidenceConcentration);
  for (const auto* k : {&kImuRate, &kGyroNoise, &kGyroWalk, &kAccelNoise, &kAccelWalk}) s.add(*k);
  s.add(kImuNoise);
  for (const auto* k : {&kInitialGyroBias, &kInitialAccelBias, &kGyroMisalignment, &kAccelMisalignment, &kShocks})
    s.add(*k);
  s.add(kGpsEnabled).add(kGpsRate).add(kGpsSigmaHorizontal).add(kGpsSigmaVertical).add(kGpsMultipath);
  s.add(kGpsMultipathTau).add(kGpsMultipathHorizontal).add(kGpsMultipathVertical).add(kGpsCanyonGain).add(kGpsNoise);
  s.add(kGpsOutages).add(kGpsOutageCanyon);
  s.add(kMagEnabled).add(kMagRate).add(kMagSigma).add(kMagHardIron).add(kMagSoftIron).add(kMagNoise);
  s.add(kLandmarkSpacing).add(kRaysPerSeed).add(kMaxObservationRange).add(kFeaturePixelSigma).add(kMaxPerFrame);
  return s;
}

ConfigSchema config_schema() {
  return simulation_config_schema().add(user_model_schema()).add(hand_motion_config_schema()).add(reach_model_schema());
}

std::string read_scenario_name(const Config& c) { return get(c, scenario_key()); }

ScenarioOptions read_scenario_options(const Config& c) {
  ScenarioOptions o;
  o.seed = static_cast<std::uint64_t>(get(c, kWorldSeed));
  o.people = get(c, kPeople);
  o.vehicles = get(c, kVehicles);
  o.targets = get(c, kTargets);
  o.random_layout = get(c, kLayout) == "random";
  return o;
}

SimulationConfig read_simulation_config(const Config& c, const Scenario& scenario) {
  SimulationConfig s;
  s.scenario = scenario.name;
  s.scenario_options = read_scenario_options(c);
  s.mount = mount_preset(get(c, defaulting_to(mount_key(), scenario.default_mount)));
  // The camera's downward pitch on its mount, when not the mount's own (a hand pointing level).
  s.mount.camera_pitch_rad = get(c, defaulting_to(kMountPitch, s.mount.camera_pitch_rad * 180.0 / M_PI)) * M_PI / 180.0;
  s.sensor_preset = get(c, defaulting_to(sensor_preset_key(), s.mount.default_sensor));
  const SensorPreset preset = sensor_preset(s.sensor_preset);
  s.seed = static_cast<std::uint64_t>(get(c, kSeed));
  s.duration_s = get(c, kDuration);
  s.still_time_s = get(c, kStillTime);
  s.laps = get(c, kLaps);
  s.mode = get(c, kMode) == "images" ? SimulationMode::kImages : SimulationMode::kFeatures;

  WalkerConfig& w = s.walker;
  w = s.mount.apply(w);
  w.speed_mps = get(c, kWalkerSpeed);
  w.step_frequency_hz = get(c, kStepFrequency);
  w.bob_amplitude_m = get(c, kBob);
  w.sway_amplitude_m = get(c, kSway);
  w.scan_amplitude_rad = get(c, defaulting_to(kScanAmplitude, w.scan_amplitude_rad));
  w.scan_period_s = get(c, defaulting_to(kScanPeriod, w.scan_period_s));

  read_camera(c, s, preset);
  read_labels(c, s);
  read_imu(c, s, preset);
  read_gps(c, s, scenario);
  read_mag(c, s);
  read_features(c, s);
  return s;
}

}  // namespace navaid::simulation
