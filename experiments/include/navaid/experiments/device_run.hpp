#pragma once
// The device half of a full-device run: every estimate the estimator makes goes through mapping
// (the map session: semantic voxel map, 2D layers, ESDF, obstacle scan), the device's guidance
// stage and the cue session (generator -> scheduler -> actuator adapter, speech), and what each
// stage did and cost is kept. The stages run on a thread of their own behind a bounded queue
// (DeviceRunOptions): in replay it blocks when full, in real time it drops the oldest estimate. Writes, into the run folder: map/, plans.csv, guidance_timeline.csv (the input
// of navaid cues), cues.csv, cues.png, speech.wav, device_stages.csv and latency.csv
// (docs/full-device-runs.md).
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

#include "navaid/core/config.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/experiments/device_preset.hpp"
#include "navaid/experiments/map_session.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::experiments {

struct DeviceRunOptions {
  /// The device's stages on a thread of their own, fed in estimate order: the estimator and the
  /// device work at once on two cores. Replay stays deterministic (the queue blocks when full, so
  /// nothing is dropped and every stage sees what it would see on one thread).
  bool threaded = true;
  /// Real time: a full queue drops its oldest estimate (counted) instead of blocking.
  bool drop_when_full = false;
  std::size_t queue_capacity = 8;  ///< estimates waiting for the device thread
  bool figures = true;             ///< cues.png
  /// Real time: plan and cue at each camera frame's arrival from the newest solved estimate
  /// carried to the frame's time through the IMU (estimation/state_prediction.hpp), instead of
  /// waiting for the frame's solve; the solved estimates build the map.
  bool predict_at_arrival = false;
  /// Sees every cue event as the cue session makes it (a simulated user in closed loop feels and
  /// hears them there).
  std::function<void(const interaction::CueEvent&)> cue_sink;
};

class DeviceRun {
 public:
  using Clock = std::chrono::steady_clock;

  /// Reads the device's keys of `config` (mapping.*, planning.*, interaction.*, device.*) before
  /// the caller rejects unknown keys; creates `out`.
  DeviceRun(const DeviceSpec& spec, const Config& config, const io::Recording& recording,
            const std::filesystem::path& recording_dir, const CameraCalibration& camera,
            const std::filesystem::path& out, const MapSessionOptions& map_options, const DeviceRunOptions& options);
  ~DeviceRun();
  DeviceRun(const DeviceRun&) = delete;
  DeviceRun& operator=(const DeviceRun&) = delete;

  /// A camera frame made while the run goes (the closed loop renders them), in memory or on disk,
  /// for the estimates of its time; the recording's own frames are known from the start. Unthreaded,
  /// its images are released once its estimate has been through every stage.
  void add_frame(RgbdFrame frame);

  /// One estimate, with the wall-clock time its sensor frame arrived (for the frame-to-cue latency).
  /// Estimates without a frame of the device's camera are counted and skipped. A stage's error is
  /// thrown as navaid::Error naming the stage and the frame, here (by the next call when threaded)
  /// or by finish().
  void on_estimate(const StateEstimate& estimate, Clock::time_point arrival);
  /// With predict_at_arrival: a camera frame at `t` arrived (called on the front end's thread).
  void on_frame_arrival(Timestamp t, Clock::time_point arrival);

  /// Waits for the device thread, lets the cues run out, writes the files; returns the summary
  /// (stages, latency, cues, plans, map). Rethrows a stage's error after writing what there is.
  nlohmann::ordered_json finish();

  /// The device stages' cost of one frame [ms] by its time (mapping, planning, interaction).
  struct StageTimes {
    double mapping_ms = 0, planning_ms = 0, interaction_ms = 0;
  };
  const std::map<Timestamp, StageTimes>& stage_times() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::experiments
