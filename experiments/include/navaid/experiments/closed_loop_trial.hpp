#pragma once
// One closed-loop trial (docs/simulated-users.md): a simulated user walks a scenario with a
// device. At the IMU rate the person decides (from what the device told them, after their reaction
// delay, and what their cane feels) and moves; the rig on their body samples the IMU there, and at
// the camera rate the simulator renders what the camera sees from where the person actually is
// (feature observations for the estimator, RGB-D with labels for mapping). The device is the
// full-device pipeline (device_run.hpp: the sliding-window estimator, mapping, the device's
// planning chain, cues and the actuator) and its cue events go back to the person. Contacts of the
// body and the cane with the world are counted as they begin. Without a device the person walks
// with the cane alone toward a goal they know.
//
// Deterministic: the same configuration and seeds give the same trial, bit for bit (the device
// runs unthreaded; wall-clock times are reported but drive nothing).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navaid/core/config.hpp"
#include "navaid/simulation/body_contacts.hpp"
#include "navaid/simulation/simulated_user.hpp"

namespace navaid::experiments {

struct TrialSpec {
  std::string scenario;              ///< a walk scenario (corridor, obstacle-course, ...)
  std::uint64_t world_seed = 0;      ///< the scenario's layout (0: its documented default)
  std::uint64_t seed = 1;            ///< sensor noise and the person's own randomness
  /// Everything else: a device preset's keys (device.*, estimator.*, mapping.*, planning.*,
  /// interaction.*) or none (cane only), user.* (simulated_user.hpp), sensor.* / features.* as
  /// for navaid simulate, and trial.* (docs/simulated-users.md). Unknown keys are an error.
  Config config;
  /// Write the device's run files (map/, plans, cue timelines) besides the trial's own.
  bool device_files = true;
};

/// A moment the device pointed the person into an obstacle: the direction it gave, followed for
/// trial.guidance_check_m from where the person truly was, walks the body into a static primitive.
/// Counted once per episode (consecutive such instructions are one).
struct GuidanceIntoObstacle {
  double t_s = 0;
  std::string instruction;
  double direction_deg = 0;  ///< in W
  std::uint32_t primitive = 0;
  std::string semantic;
};

struct TrialResult {
  bool success = false;
  std::string outcome;            ///< "arrived" (goal area reached), "stopped-short", "timeout"
  double duration_s = 0;          ///< from walking off to the end
  double path_length_m = 0;       ///< walked by the body
  double mean_speed_mps = 0;      ///< path length / time spent walking
  std::vector<simulation::Contact> contacts;
  std::size_t body_contacts = 0, cane_contacts = 0;
  simulation::UserCounts user;
  std::vector<GuidanceIntoObstacle> into_obstacle;
  double goal_distance_m = 0;     ///< at the end
  /// Route trials (trial.face_landmark): whether the person faced the destination's landmark at
  /// the end, and the experimenter's corrections (experimenter.hpp).
  bool faced_landmark = false;
  std::size_t experimenter_corrections = 0;
  double max_off_route_m = 0;
  double wall_s = 0;
  nlohmann::ordered_json summary; ///< what summary.json holds
};

/// Runs the trial and writes its folder (summary.json, track.csv, contacts.csv, instructions.csv,
/// config.yaml, simulation.yaml and, with device_files, the device's run files). Throws
/// ConfigError / UsageError naming the key on a bad configuration, Error when the device cannot run
/// in closed loop.
TrialResult run_trial(const TrialSpec& spec, const std::filesystem::path& out);

}  // namespace navaid::experiments
