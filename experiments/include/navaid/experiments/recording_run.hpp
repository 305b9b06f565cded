#pragma once
// One run of navaid on a recording, as `navaid run` does it, for every caller: the estimator
// (replay or real time) and, when the configuration names a device (device.*), the whole device:
// mapping, guidance, cues, speech, the stage timing, the frame-to-cue latency and report.html.
#include <filesystem>
#include <string>

#include "navaid/core/config.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/io/ros_bag.hpp"

namespace navaid::experiments {

struct RecordingRunOptions {
  std::filesystem::path recording, out;
  Config config;  ///< estimator.*, frontend.*, mapping.*, and for a device device.*, planning.*, interaction.*
  bool realtime = false;
  runtime::RealtimeOptions realtime_options;
  std::size_t device_queue = 8;  ///< real time: estimates that may wait for the device thread
  /// With a device: what the user says (read_voice_commands), at its seconds from the recording's
  /// start (its earliest sensor sample, as mapping.network.outages count).
  std::filesystem::path voice;
  bool plot = true;              ///< topview.png, cues.png, report.html
  /// Image input: the front end's tracks are also saved here as a feature-level recording (the
  /// recording without its images, features.csv the tracks), so that the same tracks can run
  /// through a back end alone: navaid's, or a peer's (front-end / back-end split). Empty: none.
  std::filesystem::path save_features;
  /// A ROS bag as the recording is first converted into out/recording with these options.
  io::RosBagConversion bag;
  bool bag_options_given = false;  ///< bag options for a recording that is not a bag are an error
};

/// Runs and writes the run folder; returns the one-line summary for the console. Throws
/// UsageError / ConfigError / IoError / Error with the file, key, stage or frame named; a stage
/// that fails mid-run leaves everything written so far in the run folder (error.txt says what).
std::string run_recording(const RecordingRunOptions& options);

}  // namespace navaid::experiments
