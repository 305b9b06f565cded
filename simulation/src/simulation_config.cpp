#include "navaid/simulation/simulation_config.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "navaid/core/errors.hpp"

namespace navaid::simulation {

namespace {

Vec3 get_vec3(const Config& c, const char* key, const Vec3& fallback, Range allowed) {
  if (!c.has(key)) return fallback;
  const auto v = c.get_doubles(key, 3, allowed);
  return Vec3(v[0], v[1], v[2]);
}

// A 3x3 matrix given row by row as 9 numbers.
Mat3 get_mat3(const Config& c, const char* key, const Mat3& fallback) {
  if (!c.has(key)) return fallback;
  const auto v = c.get_doubles(key, 9, {-10, 10});
  Mat3 m;
  m << v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8];
  return m;
}

void read_camera(const Config& c, SimulationConfig& s, const SensorPreset& preset) {
  CameraCalibration cam = preset.camera;
  if (c.has("sensor.camera.resolution")) {
    const auto res = c.get_doubles("sensor.camera.resolution", 2, {16, 4096});
    cam = rescale_camera(cam, static_cast<int>(res[0]), static_cast<int>(res[1]));
  }
  cam.rate_hz = c.get_double("sensor.camera.rate", cam.rate_hz, {1, 120});
  cam.depth_min_m = c.get_double("sensor.depth.min", cam.depth_min_m, {0.05, 20});
  cam.depth_max_m = c.get_double("sensor.depth.max", cam.depth_max_m, {cam.depth_min_m, 60});
  cam.depth_baseline_m = c.get_double("sensor.depth.baseline", cam.depth_baseline_m, {1e-3, 1});
  cam.depth_disparity_sigma_px = c.get_double("sensor.depth.disparity_sigma", cam.depth_disparity_sigma_px, {0, 5});
  cam.T_B_C = s.mount.T_B_C();
  // A real rig's clocks disagree by milliseconds; 0.1 s bounds what an estimator can still find.
  s.camera_time_offset_s = c.get_double("sensor.camera.time_offset", 0.0, {-0.1, 0.1});
  cam.time_offset_s = c.get_double("sensor.camera.time_offset_calibrated", s.camera_time_offset_s, {-0.1, 0.1});
  s.camera = cam;

  RgbdNoiseConfig& n = s.rgbd_noise;
  n = rgbd_noise_config(cam);
  n.noise = c.get_bool("sensor.noise", true);
  n.depth_noise = c.get_bool("sensor.depth.noise", n.depth_noise);
  n.disparity_quantization_px = c.get_double("sensor.depth.disparity_quantization", n.disparity_quantization_px, {0, 1});
  n.edge_relative_jump = c.get_double("sensor.depth.edge_relative_jump", n.edge_relative_jump, {1e-3, 10});
  n.edge_dropout_probability = c.get_double("sensor.depth.edge_dropout", n.edge_dropout_probability, {0, 1});
  n.flying_pixel_probability = c.get_double("sensor.depth.flying_pixels", n.flying_pixel_probability, {0, 1});
  n.dropout_probability = c.get_double("sensor.depth.dropout", n.dropout_probability, {0, 1});
  n.intensity_noise = c.get_bool("sensor.intensity.noise", n.intensity_noise);
  n.intensity_sigma = c.get_double("sensor.intensity.sigma", n.intensity_sigma, {0, 50});
  n.intensity_shot_gain = c.get_double("sensor.intensity.shot_gain", n.intensity_shot_gain, {0, 10});
  validate(n, "sensor.depth");

  // Rendered a little beyond the sensor's range so that noise can carry a depth across the limit.
  s.render.min_depth = 0.5 * cam.depth_min_m;
  s.render.max_depth = 1.2 * cam.depth_max_m;
}

void read_labels(const Config& c, SimulationConfig& s) {
  LabelConfusionConfig& l = s.label_confusion;
  l.noise = c.get_bool("sensor.noise", true) && c.get_bool("sensor.labels.noise", l.noise);
  for (const auto& name : c.child_keys("sensor.labels.accuracy")) {
    const SemanticClass cls = semantic_class_from_name(name);
    l.accuracy[static_cast<std::size_t>(cls)] = c.get_double("sensor.labels.accuracy." + name, {1e-3, 1});
  }
  l.cell_size_px = static_cast<int>(c.get_int("sensor.labels.cell_size", l.cell_size_px, 1, 4096));
  l.boundary_width_px = static_cast<int>(c.get_int("sensor.labels.boundary_width", l.boundary_width_px, 0, 16));
  l.boundary_probability = c.get_double("sensor.labels.boundary_probability", l.boundary_probability, {0, 1});
  l.confidence_concentration =
      c.get_double("sensor.labels.confidence_concentration", l.confidence_concentration, {1e-3, 1e4});
  validate(l, "sensor.labels");
}

void read_imu(const Config& c, SimulationConfig& s, const SensorPreset& preset) {
  ImuCalibration imu = preset.imu;
  imu.rate_hz = c.get_double("sensor.imu.rate", imu.rate_hz, {50, 2000});
  imu.gyro_noise_density = c.get_double("sensor.imu.gyro_noise_density", imu.gyro_noise_density, {0, 1});
  imu.gyro_random_walk = c.get_double("sensor.imu.gyro_random_walk", imu.gyro_random_walk, {0, 1});
  imu.accel_noise_density = c.get_double("sensor.imu.accel_noise_density", imu.accel_noise_density, {0, 10});
  imu.accel_random_walk = c.get_double("sensor.imu.accel_random_walk", imu.accel_random_walk, {0, 10});
  s.imu = imu;
  const bool noise = c.get_bool("sensor.noise", true) && c.get_bool("sensor.imu.noise", true);
  s.imu_options.white_noise = noise;
  s.imu_options.bias_walk = noise;
  s.imu_options.initial_gyro_bias = get_vec3(c, "sensor.imu.initial_gyro_bias", Vec3::Zero(), {-1, 1});
  s.imu_options.initial_accel_bias = get_vec3(c, "sensor.imu.initial_accel_bias", Vec3::Zero(), {-5, 5});
  s.imu_options.gyro_scale_misalignment = get_mat3(c, "sensor.imu.gyro_scale_misalignment", Mat3::Identity());
  s.imu_options.accel_scale_misalignment = get_mat3(c, "sensor.imu.accel_scale_misalignment", Mat3::Identity());
  if (c.has("sensor.imu.shocks")) {  // [start, duration, ax, ay, az, ...]: seconds since the walk starts, m/s^2
    const auto v = c.get_doubles("sensor.imu.shocks", 0, {-1e6, 1e6});
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
  s.gps_enabled = c.get_bool("sensor.gps.enabled", outdoor);
  GnssModelConfig& g = s.gps;
  g.rate_hz = c.get_double("sensor.gps.rate", g.rate_hz, {1, 10});
  g.sigma_horizontal_m = c.get_double("sensor.gps.sigma_horizontal", g.sigma_horizontal_m, {0, 100});
  g.sigma_vertical_m = c.get_double("sensor.gps.sigma_vertical", g.sigma_vertical_m, {0, 100});
  const bool multipath = c.get_bool("sensor.gps.multipath", true);
  g.multipath_tau_s = c.get_double("sensor.gps.multipath_tau", g.multipath_tau_s, {0.1, 3600});
  g.multipath_sigma_horizontal_m =
      multipath ? c.get_double("sensor.gps.multipath_sigma_horizontal", g.multipath_sigma_horizontal_m, {0, 100}) : 0.0;
  g.multipath_sigma_vertical_m =
      multipath ? c.get_double("sensor.gps.multipath_sigma_vertical", g.multipath_sigma_vertical_m, {0, 100}) : 0.0;
  g.canyon_gain = c.get_double("sensor.gps.canyon_gain", g.canyon_gain, {0, 100});
  g.noise = c.get_bool("sensor.noise", true) && c.get_bool("sensor.gps.noise", true);
  if (c.has("sensor.gps.outages")) {  // [start, end, start, end, ...] seconds since the walk starts
    const auto v = c.get_doubles("sensor.gps.outages", 0, {-60, 1e6});
    if (v.size() % 2 != 0)
      throw ConfigError(c.origin("sensor.gps.outages"), "sensor.gps.outages", "needs pairs [start, end, ...] in seconds");
    for (std::size_t i = 0; i < v.size(); i += 2)
      g.outages.push_back({kSimulationEpoch + seconds_to_ns(v[i]), kSimulationEpoch + seconds_to_ns(v[i + 1])});
  }
  if (c.has("sensor.gps.outage_canyon_factor"))
    g.outage_canyon_factor = c.get_double("sensor.gps.outage_canyon_factor", {0, 1});
  validate(g, "sensor.gps");
}

void read_mag(const Config& c, SimulationConfig& s) {
  s.mag_enabled = c.get_bool("sensor.mag.enabled", true);
  s.mag_rate_hz = c.get_double("sensor.mag.rate", s.mag_rate_hz, {1, 1000});
  s.mag.sigma_t = c.get_double("sensor.mag.sigma", s.mag.sigma_t, {0, 1e-4});
  s.mag.hard_iron_t = get_vec3(c, "sensor.mag.hard_iron", s.mag.hard_iron_t, {-1e-3, 1e-3});
  s.mag.soft_iron = get_mat3(c, "sensor.mag.soft_iron", s.mag.soft_iron);
  s.mag.noise = c.get_bool("sensor.noise", true) && c.get_bool("sensor.mag.noise", true);
  validate(s.mag, "sensor.mag");
}

void read_features(const Config& c, SimulationConfig& s) {
  FeatureSimConfig& f = s.features;
  f.landmark_spacing_m = c.get_double("features.landmark_spacing", f.landmark_spacing_m, {0.05, 100});
  f.rays_per_seed_point = static_cast<int>(c.get_int("features.rays_per_seed_point", f.rays_per_seed_point, 1, 10000));
  f.max_observation_range_m = c.get_double("features.max_observation_range", f.max_observation_range_m, {0.5, 200});
  f.pixel_sigma_px = c.get_double("features.pixel_sigma", f.pixel_sigma_px, {0, 20});
  if (!c.get_bool("sensor.noise", true)) f.pixel_sigma_px = 0.0;
  // Same switches as the image mode's depth noise; the calibration keeps the sensor's sigma.
  if (!s.rgbd_noise.noise || !s.rgbd_noise.depth_noise) f.disparity_sigma_px = 0.0;
  f.max_features_per_frame = static_cast<int>(c.get_int("features.max_per_frame", f.max_features_per_frame, 1, 5000));
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

std::string read_scenario_name(const Config& c) { return c.get_string("scenario", scenario_names()); }

ScenarioOptions read_scenario_options(const Config& c) {
  ScenarioOptions o;
  o.seed = static_cast<std::uint64_t>(c.get_int("simulation.world_seed", 0, 0, std::numeric_limits<long long>::max()));
  o.people = c.get_bool("simulation.people", o.people);
  o.vehicles = c.get_bool("simulation.vehicles", o.vehicles);
  o.targets = c.get_bool("simulation.targets", o.targets);
  o.random_layout = c.get_string("simulation.layout", "default", {"default", "random"}) == "random";
  return o;
}

SimulationConfig read_simulation_config(const Config& c, const Scenario& scenario) {
  SimulationConfig s;
  s.scenario = scenario.name;
  s.scenario_options = read_scenario_options(c);
  s.mount = mount_preset(c.get_string("mount", scenario.default_mount, mount_names()));
  // The camera's downward pitch on its mount, when not the mount's own (a hand pointing level).
  s.mount.camera_pitch_rad = c.get_double("mount_pitch_deg", s.mount.camera_pitch_rad * 180.0 / M_PI, {-60.0, 60.0}) * M_PI / 180.0;
  s.sensor_preset = c.get_string("sensor.preset", s.mount.default_sensor, sensor_preset_names());
  const SensorPreset preset = sensor_preset(s.sensor_preset);
  s.seed = static_cast<std::uint64_t>(c.get_int("seed", 0, 0, std::numeric_limits<long long>::max()));
  s.duration_s = c.get_double("duration", 0.0, {0, 1e6});
  s.still_time_s = c.get_double("simulation.still_time", s.still_time_s, {0, 60});
  s.laps = static_cast<int>(c.get_int("simulation.laps", s.laps, 1, 10000));
  s.mode = c.get_string("simulation.mode", "images", {"images", "features"}) == "images" ? SimulationMode::kImages
                                                                                          : SimulationMode::kFeatures;

  WalkerConfig& w = s.walker;
  w = s.mount.apply(w);
  w.speed_mps = c.get_double("walker.speed", w.speed_mps, {0.2, 3});
  w.step_frequency_hz = c.get_double("walker.step_frequency", w.step_frequency_hz, {0.5, 4});
  w.bob_amplitude_m = c.get_double("walker.bob_amplitude", w.bob_amplitude_m, {0, 0.2});
  w.sway_amplitude_m = c.get_double("walker.sway_amplitude", w.sway_amplitude_m, {0, 0.2});
  w.scan_amplitude_rad = c.get_double("walker.scan_amplitude", w.scan_amplitude_rad, {0, 1.5});
  w.scan_period_s = c.get_double("walker.scan_period", w.scan_period_s, {0.2, 60});

  read_camera(c, s, preset);
  read_labels(c, s);
  read_imu(c, s, preset);
  read_gps(c, s, scenario);
  read_mag(c, s);
  read_features(c, s);
  return s;
}

}  // namespace navaid::simulation
