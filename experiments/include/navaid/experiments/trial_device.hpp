#pragma once
// The device a simulated person carries in a closed-loop trial: the rig's sensors rendered online
// from the true state, the estimator fed through runtime::EstimatorDriver and the device's stages
// through a runtime::Device (kept as the trial's run folder by DeviceRun), one IMU tick at a time.
// Its cues go to the caller's sink: the person feels and hears them before the next tick.
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/walker_trajectory.hpp"

namespace navaid::experiments {

struct TrialDeviceOptions {
  CameraCalibration render_camera;  ///< what the camera renders for mapping (a lower resolution)
  double camera_rate_hz = 10;       ///< the rate features and frames come at
  /// trial.save_recording: the sensor streams and true states as a navaid recording (recording/).
  bool save_recording = false;
  std::function<void(const interaction::CueEvent&)> cue_sink;
};

/// What the device's half of a trial cost and saw.
struct TrialDeviceCounts {
  double sensor_s = 0, estimator_s = 0, device_s = 0;  ///< wall clock
  std::uint64_t frames = 0;
  std::size_t gps_fixes = 0, mag_samples = 0;
};

class TrialDevice {
 public:
  /// Reads the estimator's and the device's keys of `config`; writes into `out`. `nominal`: the
  /// walk the sensors seed their landmarks along.
  TrialDevice(const runtime::DeviceSpec& spec, const Config& config, const simulation::Scenario& scenario,
              const simulation::SimulationConfig& sim, const simulation::WalkerTrajectory& nominal,
              const std::filesystem::path& out, const TrialDeviceOptions& options);
  ~TrialDevice();

  /// Renders the sensors for the recording's clock `t` (one IMU tick, the camera and GNSS when
  /// due) and runs them through the estimator and the device.
  void step(const simulation::KinematicState& state, Timestamp t);
  /// The newest estimate (what the device believes), none before the first.
  const std::optional<StateEstimate>& last_estimate() const;

  /// Lets the device finish (its files, recording/ when saving); its summary.
  nlohmann::ordered_json finish();
  /// The estimator's failures, restarts, resets, registrations.
  nlohmann::ordered_json estimator_summary() const;
  const TrialDeviceCounts& counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::experiments
