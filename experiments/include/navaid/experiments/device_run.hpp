#pragma once
// A device on a recording, kept as a run folder: runtime::Device (runtime/device.hpp) with the
// mission the recording says (recording_mission.hpp) and sinks that write, into the run folder,
// map/ (MapSession), plans.csv, guidance_timeline.csv (the input of navaid cues), latency.csv and
// device_stages.csv as the frames go, and cues.csv, cues.png and speech.wav at the end
// (docs/full-device-runs.md).
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/runtime/device.hpp"

namespace navaid::experiments {

struct DeviceRunOptions {
  runtime::DeviceOptions device;  ///< threads, queues, prediction, the mapping stage's options
  bool figures = true;            ///< cues.png
  /// Sees every cue event as the cue session makes it (a simulated user in closed loop feels and
  /// hears them there).
  std::function<void(const interaction::CueEvent&)> cue_sink;
  /// Sees every estimate the device is handed or makes (what it believes).
  std::function<void(const StateEstimate&)> estimate_sink;
};

class DeviceRun {
 public:
  /// Reads the device's keys of `config` (mapping.*, planning.*, interaction.*, device.*) before
  /// the caller rejects unknown keys; hands the device the recording's frames of `camera` and
  /// its IMU; creates `out`.
  DeviceRun(const runtime::DeviceSpec& spec, const Config& config, const io::Recording& recording,
            const std::filesystem::path& recording_dir, const CameraCalibration& camera,
            const std::filesystem::path& out, const MapSessionOptions& map_options, const DeviceRunOptions& options);
  ~DeviceRun();
  DeviceRun(const DeviceRun&) = delete;
  DeviceRun& operator=(const DeviceRun&) = delete;

  runtime::Device& device();

  /// Waits for the device, writes the files; returns the summary (stages, latency, cues, plans,
  /// map). Rethrows a stage's error after writing what there is.
  nlohmann::ordered_json finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::experiments
