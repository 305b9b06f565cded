#include "navaid/experiments/device_run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <fstream>

#include "navaid/core/csv_field.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/figure_script.hpp"
#include "navaid/experiments/recording_mission.hpp"
#include "navaid/interaction/cue_timeline_csv.hpp"
#include "navaid/interaction/device_adapter.hpp"
#include "navaid/interaction/speech_mix.hpp"
#include "navaid/interaction/wav_file.hpp"

#include "csv_output.hpp"

namespace navaid::experiments {

namespace {

std::string path_text(const std::vector<mapping::Vec2>& path) {
  std::string s;
  for (const auto& p : path) s += fmt::format("{}{:.3f}:{:.3f}", s.empty() ? "" : " ", p.x(), p.y());
  return s;
}

}  // namespace

struct DeviceRun::Impl {
  Impl(const runtime::DeviceSpec& s, const Config& config, const io::Recording& recording,
       const std::filesystem::path& recording_dir, const CameraCalibration& camera, const std::filesystem::path& out_dir,
       const MapSessionOptions& map_options, const DeviceRunOptions& o)
      : spec(s), options(o), out(out_dir) {
    std::filesystem::create_directories(out);
    plans_csv = open_csv(out / "plans.csv", "t_ns,planner,status,reason,length_m,expanded,time_ms,path");
    latency_csv = open_csv(out / "latency.csv", "frame_t_ns,cue_t_s,kind,latency_ms");
    stages_csv = open_csv(out / "device_stages.csv",
                          "t_ns,frame,mapped,mapping_ms,planning_ms,interaction_ms,action,reason,detail");
    timeline.emplace(out / "guidance_timeline.csv");
    runtime::DeviceOptions device_options = o.device;
    if (recording.calibration.imu) device_options.imu_noise = estimation::ImuNoise::from(*recording.calibration.imu);
    device.emplace(spec, config, camera, recording_mission(spec, config, recording, recording_dir, out),
                   device_options, sinks());
    map.emplace(device->mapping(), recording_dir, out / "map", map_options);  // before the first estimate
    for (const auto& f : recording.frames)
      if (f.camera == camera.name) device->add_frame(&f);
    if (device_options.predict_at_arrival)
      for (const auto& sample : recording.imu) device->add_imu(sample);
  }

  runtime::DeviceSinks sinks() {
    runtime::DeviceSinks k;
    k.cue = options.cue_sink;
    k.estimate = options.estimate_sink;
    k.guidance = [this](const interaction::GuidanceTimelineEntry& entry) { timeline->add(entry); };
    k.plan = [this](Timestamp t, std::string_view planner, const planning::Plan& p) {
      plans_csv << fmt::format("{},{},{},{},{:.3f},{},{:.3f},{}\n", t, planner, p.found() ? "found" : "not-found",
                               planning::to_string(p.reason), p.length_m, p.expanded, 1e3 * p.time_s, path_text(p.path_W));
    };
    k.latency = [this](const runtime::CueLatency& l) {
      latency_csv << fmt::format("{},{:.3f},{},{:.3f}\n", l.frame_t, ns_to_seconds(l.event.t - l.origin),
                                 interaction::to_string(l.event.cue.kind), l.latency_ms);
    };
    k.frame = [this](const runtime::DeviceFrameLog& f) {
      stages_csv << fmt::format("{},{},{},{:.4f},{:.4f},{:.4f},{},{},{}\n", f.t, f.frame, f.mapped ? 1 : 0,
                                f.times.mapping_ms, f.times.planning_ms, f.times.interaction_ms,
                                planning::to_string(f.command.action), planning::to_string(f.command.reason),
                                csv_field(f.command.detail));
    };
    k.map = [this](const RgbdFrame& frame, const StateEstimate& e, const runtime::MappedFrame& mapped,
                   const runtime::MappingStage&) { map->record(frame, e, mapped); };
    return k;
  }

  nlohmann::ordered_json finish() {
    runtime::DeviceResult r = device->finish();
    for (auto* f : {&plans_csv, &latency_csv, &stages_csv}) f->flush();
    timeline->close();
    interaction::write_cue_timeline_csv(out / "cues.csv", r.events);
    double speech_s = 0;
    const interaction::SynthesizedSpeech* speech = device->speech();
    if (speech && !speech->config().text_only) {
      const interaction::AudioBuffer mix = interaction::mix_spoken_audio(r.events, *speech, r.origin.value_or(0));
      interaction::write_wav(out / "speech.wav", mix);
      speech_s = mix.duration_s();
    }
    nlohmann::ordered_json j = std::move(r.summary);
    j["cues"]["speech_wav_s"] = speech_s;
    const auto m = map->finish({{"poses", "the estimator's, as the run went"}});
    j["mapping"] = {{"folder", "map"}, {"frames", m["frames"]}};
    if (m.contains("quality")) j["mapping"]["quality"] = m["quality"]["occupancy"];
    if (options.figures) draw_cues();
    if (r.error) std::rethrow_exception(r.error);
    return j;
  }

  void draw_cues() const {
    try {
      const interaction::DeviceAdapter& actuator = device->actuator();
      std::string names;
      for (int i = 0; i < actuator.actuator_count(); ++i) names += (i ? "," : "") + std::string(actuator.actuator_name(i));
      run_figure_script("plot_cues.py", {(out / "cues.csv").string(), "--actuators", names, "--device",
                                         std::string(interaction::to_string(spec.actuator)), "--out",
                                         (out / "cues.png").string()});
    } catch (const std::exception& e) {
      spdlog::warn("cues.png not drawn: {}", e.what());
    }
  }

  runtime::DeviceSpec spec;
  DeviceRunOptions options;
  std::filesystem::path out;
  std::ofstream plans_csv, latency_csv, stages_csv;  // written as the frames go
  std::optional<interaction::GuidanceTimelineWriter> timeline;
  std::optional<MapSession> map;  // map/, fed on the device's mapping thread
  std::optional<runtime::Device> device;  // last: its threads stop before the sinks' files close
};

DeviceRun::DeviceRun(const runtime::DeviceSpec& spec, const Config& config, const io::Recording& recording,
                     const std::filesystem::path& recording_dir, const CameraCalibration& camera,
                     const std::filesystem::path& out, const MapSessionOptions& map_options,
                     const DeviceRunOptions& options)
    : impl_(std::make_unique<Impl>(spec, config, recording, recording_dir, camera, out, map_options, options)) {}

DeviceRun::~DeviceRun() = default;

runtime::Device& DeviceRun::device() { return *impl_->device; }

nlohmann::ordered_json DeviceRun::finish() { return impl_->finish(); }

}  // namespace navaid::experiments
