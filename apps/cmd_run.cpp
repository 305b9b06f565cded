// navaid run: the command line of experiments::run_recording (recording_run.hpp): the estimator on
// a recording and, with --device, the whole device (docs/estimator.md "navaid run",
// docs/full-device-runs.md).
#include <iostream>
#include <memory>

#include "bag_options.hpp"
#include "commands.hpp"
#include "navaid/core/config.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/runtime/device_spec.hpp"
#include "navaid/experiments/recording_run.hpp"

namespace navaid::cli {

namespace {

struct RunArgs {
  std::filesystem::path recording, out, config_file;
  std::string device;
  std::filesystem::path voice;
  std::filesystem::path save_features;
  std::vector<std::string> overrides;
  bool realtime = false;
  runtime::RealtimeOptions realtime_options;
  std::size_t device_queue = 8;
  bool no_plot = false;
  BagOptions bag;
};

void run(const RunArgs& a) {
  if (a.recording.empty()) throw UsageError("--recording is required");
  if (a.out.empty()) throw UsageError("--out is required");
  if (!a.device.empty() && !a.config_file.empty())
    throw UsageError("give --device NAME (a preset) or --config FILE, not both; change a preset's keys with --set");
  if (a.realtime) runtime::validate(a.realtime_options);
  if (a.device_queue == 0) throw UsageError("--device-queue must be at least 1");
  if (!a.voice.empty() && a.device.empty() && a.config_file.empty()) throw UsageError("--voice needs a device (--device)");
  experiments::RecordingRunOptions o;
  o.recording = a.recording;
  o.out = a.out;
  const std::filesystem::path file = a.device.empty() ? a.config_file : runtime::device_preset_file(a.device);
  o.config = file.empty() ? Config::parse("{}", "<defaults>", a.overrides) : Config::load(file, a.overrides);
  o.realtime = a.realtime;
  o.realtime_options = a.realtime_options;
  o.device_queue = a.device_queue;
  o.voice = a.voice;
  o.save_features = a.save_features;
  o.plot = !a.no_plot;
  o.bag = a.bag.conversion();
  o.bag_options_given = a.bag.given();
  std::cout << experiments::run_recording(o);
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "Run the sliding-window estimator on a recording (features or images)");
  auto a = std::make_shared<RunArgs>();
  cmd->add_option("--recording", a->recording,
                  "Recording: navaid (feature observations or images), EuRoC or TUM RGB-D folder, or a ROS bag (converted "
                  "into OUT/recording first, docs/ros.md)");
  cmd->add_option("--out", a->out, "Run folder to write (trajectory.tum, estimates.csv, timing.csv, summary.json)");
  cmd->add_option("--config", a->config_file, "YAML configuration (estimator.* and frontend.* keys, docs/estimator.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--device", a->device,
                  "Full-device run with a preset of runtime/devices (elabrador, smart-cane, augmented-cane, "
                  "w-roma): mapping, guidance, cues, speech, report.html (docs/full-device-runs.md)");
  cmd->add_option("--voice", a->voice,
                  "With --device: what the user says as the device runs, a guidance timeline of voice_command events "
                  "(navaid listen's voice_event.csv; times in s from the recording's start): repeat, where am i, stop "
                  "guidance, go to <place> (a route's landmark)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--save-features", a->save_features,
                  "Image input: also save the front end's tracks as a feature-level recording in this folder (the "
                  "recording without images, features.csv the tracks), to run them through a back end alone");
  cmd->add_option("--device-queue", a->device_queue,
                  "With --device --realtime: estimates that may wait for the device thread (the oldest is dropped)")
      ->capture_default_str();
  cmd->add_option("--set", a->overrides, "Override a key, e.g. --set estimator.depth.enabled=false (repeatable)");
  cmd->add_flag("--realtime", a->realtime,
                "Front end and estimator on their own threads (default: deterministic single-threaded replay)");
  auto* speed = cmd->add_option("--realtime-speed", a->realtime_options.speed,
                                "With --realtime: frames arrive at this multiple of the recording's clock; 0 = as fast "
                                "as possible, nothing dropped")
                    ->capture_default_str();
  auto* queue = cmd->add_option("--realtime-queue", a->realtime_options.queue_capacity,
                                "With --realtime: tracked frames that may wait for the estimator")
                    ->capture_default_str();
  cmd->add_flag("--no-plot", a->no_plot, "Do not draw topview.png");
  a->bag.add_to(*cmd);
  cmd->callback([a, speed, queue] {
    if (!a->realtime && (speed->count() > 0 || queue->count() > 0))
      throw UsageError("--realtime-speed and --realtime-queue need --realtime");
    run(*a);
  });
}

}  // namespace navaid::cli
