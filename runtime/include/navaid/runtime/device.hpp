#pragma once
// The device half of the pipeline: every estimate the estimator makes goes through the mapping
// stage (mapping_stage.hpp), the device's guidance stage (guidance_stage.hpp) and the cue session
// (generator -> scheduler -> actuator adapter, speech). What each stage makes goes to the
// caller's sinks (DeviceSinks); the device writes no files and never sees ground truth. The
// stages run on two threads of their own behind bounded queues (DeviceOptions): in replay a full
// queue blocks, so outputs are deterministic; in real time it drops the oldest estimate (counted).
//
// Two ways in. With an estimator (set_estimator), the device takes sensor events (add: IMU,
// camera frames with depth and labels or their features, GNSS, magnetometer) and runs them
// through runtime::EstimatorDriver itself: replay's device runs and closed-loop trials. Without,
// the caller's estimator hands it estimates (on_estimate): the real-time pipeline, whose front end
// and estimator have threads of their own. Either way the user may speak (on_voice_command) or
// set a new destination (set_mission) while it runs.
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/imu_preintegration.hpp"
#include "navaid/interaction/cue_scheduler.hpp"
#include "navaid/interaction/voice_command.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/interaction/synthesized_speech.hpp"
#include "navaid/planning/local_planner.hpp"
#include "navaid/runtime/device_mission.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/runtime/mapping_stage.hpp"

namespace navaid::runtime {

class EstimatorDriver;

struct DeviceOptions {
  /// The device's stages on threads of their own (mapping; planning + cues), fed in estimate
  /// order: the estimator and the device work at once. Replay stays deterministic (the queues
  /// block when full, so every stage sees what it would see on one thread).
  bool threaded = true;
  /// Real time: a full queue drops its oldest estimate (counted) instead of blocking.
  bool drop_when_full = false;
  std::size_t queue_capacity = 8;  ///< estimates waiting for each device thread
  /// Real time: plan and cue at each camera frame's arrival from the newest solved estimate
  /// carried to the frame's time through the IMU (add_imu; estimation/state_prediction.hpp),
  /// instead of waiting for the frame's solve; the solved estimates build the map.
  bool predict_at_arrival = false;
  estimation::ImuNoise imu_noise;  ///< the IMU's noise, for the prediction's covariance
  MappingStageOptions mapping;
};

using Clock = std::chrono::steady_clock;

/// The device's stage times of one frame [ms].
struct StageTimes {
  double mapping_ms = 0, planning_ms = 0, interaction_ms = 0;
};

/// What the device did with one frame's estimate, once planning and cues are done.
struct DeviceFrameLog {
  Timestamp t = 0;
  std::size_t frame = 0;  ///< the frame's index
  bool mapped = false;
  StageTimes times;
  planning::GuidanceCommand command;
};

/// A cue that a frame caused, with the wall-clock time from the frame's arrival to the moment it
/// was handed to the actuator or speaker.
struct CueLatency {
  Timestamp frame_t = 0;
  const interaction::CueEvent& event;
  double latency_ms = 0;
  Timestamp origin = 0;  ///< the cue clock's zero (DeviceResult::origin)
};

/// Where the device's outputs go. Every sink is optional; they are called on the device's
/// threads (map: the mapping thread; the others: the planning thread), one at a time each.
struct DeviceSinks {
  /// Each estimate the device is handed or makes (with its covariance), on the caller's thread.
  std::function<void(const StateEstimate&)> estimate;
  /// Each cue event as the cue session makes it (actuator patterns, speech; a simulated user in
  /// closed loop feels and hears them here).
  std::function<void(const interaction::CueEvent&)> cue;
  /// Each entry handed to the cue session: guidance commands and system events.
  std::function<void(const interaction::GuidanceTimelineEntry&)> guidance;
  /// Each plan a planner made: the frame's time, the planner's name, the plan.
  std::function<void(Timestamp, std::string_view, const planning::Plan&)> plan;
  std::function<void(const CueLatency&)> latency;
  std::function<void(const DeviceFrameLog&)> frame;
  /// Each frame the mapping stage mapped, with the stage (its map, newest 2D layers and scan).
  std::function<void(const RgbdFrame&, const StateEstimate&, const MappedFrame&, const MappingStage&)> map;
};

/// What finish() hands back.
struct DeviceResult {
  nlohmann::ordered_json summary;  ///< stages, latency, guidance, plans, cues, estimates, threads
  const std::vector<interaction::CueEvent>& events;  ///< every cue event, in order
  /// The cue events' clock origin: the time of the first estimate with a frame (speech's zero).
  std::optional<Timestamp> origin;
  /// The first stage error (null when none): the caller writes what there is, then rethrows it.
  std::exception_ptr error;
};

class Device {
 public:
  /// Reads the device's keys of `config` (mapping.*, planning.*, interaction.*, device.*); the
  /// camera is the estimator's (the device maps and plans from its frames).
  Device(const DeviceSpec& spec, const Config& config, const CameraCalibration& camera, const DeviceMission& mission,
         const DeviceOptions& options, DeviceSinks sinks);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// A camera frame of the device's camera, before the estimates of its time (in memory or on
  /// disk). Unthreaded, its images are released once its estimate has been through every stage.
  void add_frame(RgbdFrame frame);
  /// A frame that stays alive at least as long as the device (a recording's): not copied.
  void add_frame(const RgbdFrame* frame);
  /// An IMU sample, for predict_at_arrival (in time order).
  void add_imu(const ImuSample& sample);

  /// The estimator add() feeds; once, before the first event.
  void set_estimator(std::unique_ptr<EstimatorDriver> estimator);
  /// One sensor event, in time order: a camera frame of the device's camera is kept for mapping
  /// and planning (add_frame), an IMU sample for the prediction (predict_at_arrival); then the
  /// event goes through the estimator and every estimate it completes through on_estimate with
  /// `arrival`. Error without an estimator.
  void add(SensorEvent event, Clock::time_point arrival = Clock::now());
  /// The input has ended (a recording's): the estimates the estimator still holds go through the
  /// stages. A closed-loop trial that stops with its walker does not call it.
  void end_of_input(Clock::time_point arrival = Clock::now());
  /// The estimator add() feeds (error without one), and the wall time add() spent in it [s].
  const EstimatorDriver& estimator() const;
  double estimator_busy_s() const;

  /// What the user asks for from time `t` on: the guidance stage is built anew for `mission` at
  /// the first estimate at or after `t` (its error is a stage error naming that frame).
  void set_mission(Timestamp t, DeviceMission mission);
  /// What the user said at time `t`, handled at the first estimate at or after `t`: the cue
  /// session answers it (repeat, where am i, stop guidance, not understood); "go to <place>"
  /// sets the mission the current mission's `place` resolves from that estimate, or is not
  /// understood when it resolves none.
  void on_voice_command(Timestamp t, const interaction::VoiceCommand& command);

  /// One estimate, with the wall-clock time its sensor frame arrived (for the frame-to-cue
  /// latency). Estimates without a frame are counted and skipped. A stage's error is thrown as
  /// navaid::Error naming the stage and the frame, here (by the next call when threaded).
  void on_estimate(const StateEstimate& estimate, Clock::time_point arrival);
  /// With predict_at_arrival: a camera frame at `t` arrived (called on the front end's thread).
  void on_frame_arrival(Timestamp t, Clock::time_point arrival);

  /// Waits for the device's threads and lets the cues run out. Call once.
  DeviceResult finish();

  /// The stage times of every frame guided so far, by its time.
  const std::map<Timestamp, StageTimes>& stage_times() const;
  const MappingStage& mapping() const;
  /// The speech renderer (null when device.speech is off).
  const interaction::SynthesizedSpeech* speech() const;
  const interaction::DeviceAdapter& actuator() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace navaid::runtime
