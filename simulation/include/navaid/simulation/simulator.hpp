#pragma once
// The simulator's driver: a scenario walked by a mounted sensor rig, written as a navaid recording
// (docs/simulate.md). Everything is seeded: the same scenario, configuration and seed give the
// same files, bit for bit, with or without a render cache and for any number of threads.
//
// Time line: the walker stands still for still_time_s (trajectory time -still_time_s .. 0), then
// walks; the recording ends at the end of the walk or after duration_s. Every sensor samples the
// exact trajectory at its own integer-nanosecond grid (time_grid.hpp) from kSimulationEpoch.
// The camera's grid is in the IMU clock too, but its frames are stamped in the camera clock:
// a frame taken at t carries t - config.camera_time_offset_s (t_imu = t_cam + offset).
// W = ENU at the scenario's geodetic origin (T_ENU_W = identity).
//
// Output folder: the navaid recording (imu, frames or features, gps, mag, groundtruth at the IMU
// rate, landmarks in feature mode) plus groundtruth.tum (body B in W, TUM format) and topview.png
// (the world from above with the walked path).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"

namespace navaid::simulation {

struct SimulateOptions {
  /// Root folder of the render cache (render_cache.hpp); none: render every frame.
  std::optional<std::filesystem::path> cache_dir;
  int threads = 0;         ///< frame workers; 0 = all cores. Never changes the output.
  bool overwrite = false;  ///< replace the recording files of a non-empty output folder
  /// Progress of the frame stage (done, total), called from one thread at a time.
  std::function<void(std::size_t, std::size_t)> on_frame;
};

struct SimulationSummary {
  double duration_s = 0;      ///< recorded time span
  double path_length_m = 0;   ///< smoothed path length of the scenario
  double walked_m = 0;        ///< distance travelled by B within the recording
  std::size_t imu = 0, frames = 0, gps = 0, mag = 0, groundtruth = 0, landmarks = 0;
  std::size_t observations = 0;        ///< feature observations (feature mode)
  double depth_observation_fraction = 0;  ///< of observations with depth (feature mode)
  double valid_depth_fraction = 0;     ///< of pixels with valid noisy depth (image mode)
  std::size_t rendered_frames = 0;     ///< frames rendered (the rest came from the cache)
  double frames_seconds = 0;           ///< wall time of the frame stage
};

/// The ground truth of the scenario's tagged target objects as targets.csv in `file`
/// (docs/recording-format.md); removes a stale file when the scenario has none.
void write_scenario_targets(const Scenario& scenario, const std::filesystem::path& file);

SimulationSummary simulate(const Scenario& scenario, const SimulationConfig& config, const std::filesystem::path& out,
                           const SimulateOptions& options = {});

}  // namespace navaid::simulation
