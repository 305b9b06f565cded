#pragma once
// Everything `navaid simulate` needs, read from a navaid::Config (YAML file + --set overrides).
// The keys, their defaults and ranges are documented in docs/simulate.md; every key read here is
// validated (ConfigError naming the key); the caller rejects unknown keys with
// config.reject_unknown_keys(simulation_config_schema()) (navaid/simulation/config_schema.hpp).
#include <cstdint>
#include <string>

#include "navaid/core/calibration.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"
#include "navaid/simulation/feature_simulator.hpp"
#include "navaid/simulation/gnss_model.hpp"
#include "navaid/simulation/imu_model.hpp"
#include "navaid/simulation/label_confusion_model.hpp"
#include "navaid/simulation/magnetometer_model.hpp"
#include "navaid/simulation/rgbd_noise_model.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/sensor_rig.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::simulation {

enum class SimulationMode { kImages, kFeatures };

/// Start of every simulated recording's clock [ns] (2024-01-01T00:00:00Z as Unix time), so that
/// time stamps look like a logger's.
constexpr Timestamp kSimulationEpoch = 1'704'067'200'000'000'000;

struct SimulationConfig {
  std::string scenario;
  ScenarioOptions scenario_options;
  Mount mount;
  std::string sensor_preset;
  std::uint64_t seed = 0;          ///< noise seed (the rendering does not depend on it)
  double duration_s = 0;           ///< 0: the whole walk
  double still_time_s = 1.0;       ///< standing still before walking off
  int laps = 1;                    ///< times round a closed path (long-walk tests)
  SimulationMode mode = SimulationMode::kImages;
  WalkerConfig walker;

  CameraCalibration camera;        ///< with T_B_C from the mount; time_offset_s as calibration.yaml says
  /// The true camera-IMU offset [s] (t_imu = t_cam + offset): a frame taken at IMU / ground-truth
  /// time t is stamped t - offset (rounded to the nanosecond).
  double camera_time_offset_s = 0;
  ImuCalibration imu;
  ImuModelOptions imu_options;     ///< seed filled in by the simulator
  RgbdNoiseConfig rgbd_noise;
  LabelConfusionConfig label_confusion;
  RenderOptions render;
  FeatureSimConfig features;

  bool gps_enabled = true;
  GnssModelConfig gps;
  bool mag_enabled = true;
  double mag_rate_hz = 50.0;
  MagnetometerModelConfig mag;
  double groundtruth_rate_hz = 0;  ///< 0: the IMU rate
};

/// Scenario keys, read before the scenario is built: `scenario` (required), `simulation.world_seed`,
/// `simulation.people`, `simulation.vehicles`.
std::string read_scenario_name(const Config& config);
ScenarioOptions read_scenario_options(const Config& config);

/// Reads the configuration. `scenario` must already be resolved (key `scenario`), because the
/// mount, the sensor preset and GPS use scenario-dependent defaults.
SimulationConfig read_simulation_config(const Config& config, const Scenario& scenario);

/// A camera calibration rescaled to another resolution of the same aspect ratio (pinhole
/// intrinsics scale with the pixel size; pixel centres stay pixel centres).
CameraCalibration rescale_camera(const CameraCalibration& camera, int width, int height);

}  // namespace navaid::simulation
