#include "navaid/experiments/device_run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <condition_variable>
#include <deque>
#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/estimator_pipeline.hpp"
#include "navaid/experiments/figure_script.hpp"
#include "navaid/experiments/guidance_stage.hpp"
#include "navaid/interaction/cue_session.hpp"
#include "navaid/interaction/cue_timeline_csv.hpp"
#include "navaid/interaction/device_adapter.hpp"
#include "navaid/interaction/guidance_timeline_csv.hpp"
#include "navaid/interaction/speech_mix.hpp"
#include "navaid/interaction/synthesized_speech.hpp"
#include "navaid/interaction/wav_file.hpp"
#include "navaid/core/csv_field.hpp"

namespace navaid::experiments {

namespace {

using Clock = DeviceRun::Clock;

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

std::ofstream open_csv(const std::filesystem::path& file, const char* header) {
  std::ofstream out(file);
  if (!out) throw IoError(file.string(), "cannot write");
  out << header << "\n";
  return out;
}

std::string path_text(const std::vector<mapping::Vec2>& path) {
  std::string s;
  for (const auto& p : path) s += fmt::format("{}{:.3f}:{:.3f}", s.empty() ? "" : " ", p.x(), p.y());
  return s;
}

}  // namespace

struct DeviceRun::Impl {
  Impl(const DeviceSpec& s, const Config& config, const io::Recording& recording, const std::filesystem::path& recording_dir,
       const CameraCalibration& camera, const std::filesystem::path& out_dir, const MapSessionOptions& map_options,
       const DeviceRunOptions& o)
      : spec(s),
        options(o),
        out(out_dir),
        generator(interaction::read_cue_generator_config(config)),
        policy(interaction::read_cue_policy_config(config)),
        device(interaction::make_device_adapter(s.actuator, config)),
        speech_config(interaction::read_speech_config(config)),
        map(mapping::read_mapper_config(config), camera, recording_dir, out_dir / "map", map_options),
        stage(make_guidance_stage({s, config, recording, recording_dir, camera, out_dir})) {
    if (spec.speech == "text") speech_config.text_only = true;
    if (spec.speech != "off") speech = std::make_unique<interaction::SynthesizedSpeech>(speech_config);
    session = std::make_unique<interaction::CueSession>(generator, policy, *device, speech.get());
    for (const auto& f : recording.frames)
      if (f.camera == camera.name) frame_at[f.t] = &f;
    plans_csv = open_csv(out / "plans.csv", "t_ns,planner,status,reason,length_m,expanded,time_ms,path");
    latency_csv = open_csv(out / "latency.csv", "frame_t_ns,cue_t_s,kind,latency_ms");
    stages_csv = open_csv(out / "device_stages.csv", "t_ns,frame,mapped,mapping_ms,planning_ms,interaction_ms,action,reason,detail");
  }

  void process(const StateEstimate& e, Clock::time_point arrival) {
    const auto it = frame_at.find(e.t);
    if (it == frame_at.end()) {
      ++without_frame;
      return;
    }
    const RgbdFrame& frame = *it->second;
    const char* stage_name = "mapping";
    try {
      StageTimes times;
      auto t0 = Clock::now();
      const bool map_this = spec.map_every > 0 && estimates % spec.map_every == 0;
      ++estimates;
      if (map_this) map.add(frame, e);
      auto t1 = Clock::now();
      times.mapping_ms = ms_between(t0, t1);

      stage_name = "planning";
      const auto& scan = map.last_obstacle_scan();
      GuidanceInput in{frame, e, map.mapper().local_maps(), scan ? &*scan : nullptr};
      GuidanceOutput g = stage->update(in);
      auto t2 = Clock::now();
      times.planning_ms = ms_between(t1, t2);
      if (g.new_plan) {
        const planning::Plan& p = *g.new_plan;
        plans_csv << fmt::format("{},{},{},{},{:.3f},{},{:.3f},{}\n", e.t, g.planner, p.found() ? "found" : "not-found",
                                 planning::to_string(p.reason), p.length_m, p.expanded, 1e3 * p.time_s,
                                 path_text(p.path_W));
        ++plans;
        plans_found += p.found() ? 1 : 0;
      }

      stage_name = "interaction";
      std::vector<interaction::GuidanceTimelineEntry> entries = map.take_system_events();
      entries.emplace_back(g.command);
      for (const auto& entry : entries) {
        timeline.push_back(entry);
        for (const interaction::CueEvent& ev : session->feed(entry)) {
          const bool reaches_user = ev.outcome == interaction::CueOutcome::kSent || ev.outcome == interaction::CueOutcome::kSpoken;
          if (!reaches_user || ev.cue.t != e.t) continue;
          // The cue this frame caused: from the frame's arrival to the moment it is handed to the
          // actuator or the speaker.
          const double latency = ms_between(arrival, Clock::now());
          latency_ms.push_back(latency);
          latency_csv << fmt::format("{},{:.3f},{},{:.3f}\n", e.t, ns_to_seconds(ev.t - t_origin(e.t)),
                                     interaction::to_string(ev.cue.kind), latency);
        }
      }
      times.interaction_ms = ms_between(t2, Clock::now());
      stage_times[e.t] = times;
      mapping_ms.push_back(times.mapping_ms);
      planning_ms.push_back(times.planning_ms);
      interaction_ms.push_back(times.interaction_ms);
      stages_csv << fmt::format("{},{},{},{:.4f},{:.4f},{:.4f},{},{},{}\n", e.t, frame.index, map_this ? 1 : 0,
                                times.mapping_ms, times.planning_ms, times.interaction_ms,
                                planning::to_string(g.command.action), planning::to_string(g.command.reason),
                                csv_field(g.command.detail));
    } catch (const std::exception& ex) {
      throw Error(fmt::format("{} stage failed at frame {} (t = {} ns): {}", stage_name, frame.index, e.t, ex.what()));
    }
  }

  /// The timeline's clock starts at the first estimate with a frame (speech.wav's zero).
  Timestamp t_origin(Timestamp t) {
    if (!origin) origin = t;
    return *origin;
  }

  // Real time: the device thread and its queue.
  void start_thread() {
    worker = std::thread([this] {
      for (;;) {
        std::pair<StateEstimate, Clock::time_point> item;
        {
          std::unique_lock<std::mutex> lock(m);
          changed.wait(lock, [&] { return !queue.empty() || closed; });
          if (queue.empty()) return;
          item = std::move(queue.front());
          queue.pop_front();
          room.notify_one();
        }
        try {
          process(item.first, item.second);
        } catch (...) {
          std::lock_guard<std::mutex> lock(m);
          error = std::current_exception();
          closed = true;
          queue.clear();
          room.notify_all();
          return;
        }
      }
    });
  }

  void push(const StateEstimate& e, Clock::time_point arrival) {
    std::unique_lock<std::mutex> lock(m);
    if (!options.drop_when_full) room.wait(lock, [&] { return error || queue.size() < options.queue_capacity; });
    if (error) std::rethrow_exception(error);  // stops the estimator: the run ends at the failed stage
    if (queue.size() >= options.queue_capacity) {
      queue.pop_front();  // the newest estimate matters most to a walking user
      ++dropped;
    }
    queue.emplace_back(e, arrival);
    max_depth = std::max(max_depth, queue.size());
    changed.notify_one();
  }

  void stop_thread() {
    {
      std::lock_guard<std::mutex> lock(m);
      closed = true;
      changed.notify_one();
    }
    if (worker.joinable()) worker.join();
  }

  DeviceSpec spec;
  DeviceRunOptions options;
  std::filesystem::path out;
  interaction::CueGeneratorConfig generator;
  interaction::CuePolicyConfig policy;
  std::unique_ptr<interaction::DeviceAdapter> device;
  interaction::SpeechConfig speech_config;
  std::unique_ptr<interaction::SynthesizedSpeech> speech;
  std::unique_ptr<interaction::CueSession> session;
  MapSession map;
  std::unique_ptr<GuidanceStage> stage;
  std::map<Timestamp, const RgbdFrame*> frame_at;
  std::ofstream plans_csv, latency_csv, stages_csv;
  std::vector<interaction::GuidanceTimelineEntry> timeline;
  std::map<Timestamp, StageTimes> stage_times;
  std::vector<double> mapping_ms, planning_ms, interaction_ms, latency_ms;
  std::size_t estimates = 0, without_frame = 0, plans = 0, plans_found = 0;
  std::optional<Timestamp> origin;

  std::thread worker;
  std::mutex m;
  std::condition_variable changed, room;
  std::deque<std::pair<StateEstimate, Clock::time_point>> queue;
  bool closed = false;
  std::exception_ptr error;
  std::size_t dropped = 0, max_depth = 0;
};

DeviceRun::DeviceRun(const DeviceSpec& spec, const Config& config, const io::Recording& recording,
                     const std::filesystem::path& recording_dir, const CameraCalibration& camera,
                     const std::filesystem::path& out, const MapSessionOptions& map_options,
                     const DeviceRunOptions& options)
    : impl_(std::make_unique<Impl>(spec, config, recording, recording_dir, camera, out, map_options, options)) {
  if (options.threaded) impl_->start_thread();
}

DeviceRun::~DeviceRun() { impl_->stop_thread(); }

void DeviceRun::on_estimate(const StateEstimate& estimate, Clock::time_point arrival) {
  if (impl_->options.threaded) {
    impl_->push(estimate, arrival);
  } else {
    impl_->process(estimate, arrival);
  }
}

const std::map<Timestamp, DeviceRun::StageTimes>& DeviceRun::stage_times() const { return impl_->stage_times; }

nlohmann::ordered_json DeviceRun::finish() {
  Impl& d = *impl_;
  d.stop_thread();
  d.session->drain();
  const std::vector<interaction::CueEvent>& events = d.session->events();
  for (auto* f : {&d.plans_csv, &d.latency_csv, &d.stages_csv}) f->flush();
  interaction::write_guidance_timeline_csv(d.out / "guidance_timeline.csv", d.timeline);
  interaction::write_cue_timeline_csv(d.out / "cues.csv", events);
  std::vector<std::string> spoken;
  for (const auto& e : events)
    if (e.outcome == interaction::CueOutcome::kSpoken) spoken.push_back(e.text);
  double speech_s = 0;
  if (d.speech && !d.speech_config.text_only) {
    const interaction::AudioBuffer mix = interaction::mix_spoken_audio(events, *d.speech, d.origin.value_or(0));
    interaction::write_wav(d.out / "speech.wav", mix);
    speech_s = mix.duration_s();
  }
  nlohmann::ordered_json counts = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < interaction::kCueOutcomeCount; ++i)
    counts[std::string(interaction::to_string(static_cast<interaction::CueOutcome>(i)))] = d.session->scheduler().counts()[i];
  nlohmann::ordered_json j;
  j["stages"] = {{"mapping", stage_distribution(d.mapping_ms)},
                 {"planning", stage_distribution(d.planning_ms)},
                 {"interaction", stage_distribution(d.interaction_ms)}};
  j["latency"] = stage_distribution(d.latency_ms);
  j["latency"]["cues"] = d.latency_ms.size();
  j["latency"]["note"] = "wall clock from a sensor frame's arrival to the cue it caused reaching the actuator or speaker";
  j["guidance"] = d.stage->summary();
  j["plans"] = {{"made", d.plans}, {"found", d.plans_found}};
  j["cues"] = {{"timeline_entries", d.timeline.size()}, {"events", events.size()}, {"outcomes", counts},
               {"spoken", spoken}, {"speech_wav_s", speech_s}};
  j["estimates"] = {{"with_frame", d.estimates}, {"without_frame", d.without_frame}};
  if (d.options.threaded)
    j["device_thread"] = {{"queue_capacity", d.options.queue_capacity}, {"when_full", d.options.drop_when_full ? "drop the oldest" : "wait"}, {"dropped", d.dropped}, {"max_depth", d.max_depth}};
  const auto m = d.map.finish({{"poses", "the estimator's, as the run went"}});
  j["mapping"] = {{"folder", "map"}, {"frames", m["frames"]}};
  if (m.contains("quality")) j["mapping"]["quality"] = m["quality"]["occupancy"];
  if (d.options.figures) {
    try {
      std::string names;
      for (int i = 0; i < d.device->actuator_count(); ++i) names += (i ? "," : "") + std::string(d.device->actuator_name(i));
      run_figure_script("plot_cues.py", {(d.out / "cues.csv").string(), "--actuators", names, "--device",
                                         std::string(interaction::to_string(d.spec.actuator)), "--out",
                                         (d.out / "cues.png").string()});
    } catch (const std::exception& e) {
      spdlog::warn("cues.png not drawn: {}", e.what());
    }
  }
  if (d.error) std::rethrow_exception(d.error);
  return j;
}

}  // namespace navaid::experiments
