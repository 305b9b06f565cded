#include "navaid/experiments/device_run.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "navaid/core/errors.hpp"
#include "navaid/runtime/bounded_queue.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/experiments/figure_script.hpp"
#include "navaid/estimation/state_prediction.hpp"
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

/// What the mapping stage leaves for the planners: the 2D maps and obstacle scan after a frame.
struct MapSnapshot {
  std::optional<mapping::LocalMaps> maps;
  std::optional<mapping::ObstacleScan> scan;
};

/// One estimate on its way through the device's stages.
struct DeviceItem {
  StateEstimate estimate;  ///< solved, or predicted to the frame's arrival
  Clock::time_point arrival;
  const RgbdFrame* frame = nullptr;
  bool mapped = false;
  double mapping_ms = 0;
  std::shared_ptr<const MapSnapshot> snapshot;  ///< replay: the map after this estimate's mapping
  std::vector<interaction::GuidanceTimelineEntry> system_events;
};

/// What the run records of one frame (device_stages.csv).
struct FrameLog {
  std::size_t frame = 0;
  bool mapped = false;
  DeviceRun::StageTimes times;
  std::string action, reason, detail;
};

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
        stage(make_guidance_stage({s, config, recording, recording_dir, camera, out_dir})),
        imu(recording.imu),
        imu_noise(recording.calibration.imu ? estimation::ImuNoise::from(*recording.calibration.imu)
                                            : estimation::ImuNoise{}),
        map_queue(o.queue_capacity, o.drop_when_full),
        guide_queue(o.queue_capacity, o.drop_when_full),
        newest(std::make_shared<MapSnapshot>()),
        timeline(out_dir / "guidance_timeline.csv") {
    if (spec.speech == "text") speech_config.text_only = true;
    if (spec.speech != "off") speech = std::make_unique<interaction::SynthesizedSpeech>(speech_config);
    session = std::make_unique<interaction::CueSession>(generator, policy, *device, speech.get(), o.cue_sink);
    for (const auto& f : recording.frames)
      if (f.camera == camera.name) frame_at[f.t] = &f;
    plans_csv = open_csv(out / "plans.csv", "t_ns,planner,status,reason,length_m,expanded,time_ms,path");
    latency_csv = open_csv(out / "latency.csv", "frame_t_ns,cue_t_s,kind,latency_ms");
    stages_csv = open_csv(out / "device_stages.csv",
                          "t_ns,frame,mapped,mapping_ms,planning_ms,interaction_ms,action,reason,detail");
  }

  /// Runs `f`, naming the stage and the frame in its error.
  template <class F>
  static void in_stage(const char* name, const DeviceItem& item, F&& f) {
    try {
      f();
    } catch (const std::exception& ex) {
      throw Error(fmt::format("{} stage failed at frame {} (t = {} ns): {}", name, item.frame->index, item.estimate.t,
                              ex.what()));
    }
  }

  /// The mapping stage: maps the frame when it is due and publishes the map it leaves.
  void map_step(DeviceItem& item) {
    item.mapped = spec.map_every > 0 && map_counter++ % spec.map_every == 0;
    const auto t0 = Clock::now();
    in_stage("mapping", item, [&] {
      if (item.mapped) map.add(*item.frame, item.estimate);
    });
    item.mapping_ms = ms_between(t0, Clock::now());
    item.system_events = map.take_system_events();
    std::shared_ptr<const MapSnapshot> snapshot;
    {
      std::lock_guard<std::mutex> lock(m);
      if (item.mapped) {
        auto next = std::make_shared<MapSnapshot>();
        if (const mapping::LocalMaps* maps = map.mapper().local_maps()) next->maps = *maps;
        next->scan = map.last_obstacle_scan();
        newest = next;
      }
      snapshot = newest;
      pending_events.insert(pending_events.end(), item.system_events.begin(), item.system_events.end());
      log[item.estimate.t].mapped = item.mapped;
      log[item.estimate.t].times.mapping_ms = item.mapping_ms;
    }
    item.snapshot = snapshot;
    mapping_ms.push_back(item.mapping_ms);
    if (item.mapped) map_latency_ms.push_back(ms_between(item.arrival, Clock::now()));
  }

  /// Planning and interaction: the guidance command on the item's map (real time: the newest),
  /// then the cues it causes.
  void guide_step(DeviceItem& item) {
    const StateEstimate& e = item.estimate;
    std::shared_ptr<const MapSnapshot> snapshot = item.snapshot;
    std::vector<interaction::GuidanceTimelineEntry> entries;
    {
      std::lock_guard<std::mutex> lock(m);
      if (!snapshot) snapshot = newest;
      entries.swap(pending_events);
    }
    FrameLog f;
    f.frame = item.frame->index;
    const auto t1 = Clock::now();
    GuidanceOutput g;
    in_stage("planning", item, [&] {
      g = stage->update({*item.frame, e, snapshot->maps ? &*snapshot->maps : nullptr,
                         snapshot->scan ? &*snapshot->scan : nullptr});
    });
    const auto t2 = Clock::now();
    f.times.planning_ms = ms_between(t1, t2);
    if (g.new_plan) {
      const planning::Plan& p = *g.new_plan;
      plans_csv << fmt::format("{},{},{},{},{:.3f},{},{:.3f},{}\n", e.t, g.planner, p.found() ? "found" : "not-found",
                               planning::to_string(p.reason), p.length_m, p.expanded, 1e3 * p.time_s, path_text(p.path_W));
      ++plans;
      plans_found += p.found() ? 1 : 0;
    }
    entries.emplace_back(g.command);
    in_stage("interaction", item, [&] {
      for (const auto& entry : entries) {
        timeline.add(entry);
        for (const interaction::CueEvent& ev : session->feed(entry)) {
          const bool reaches_user = ev.outcome == interaction::CueOutcome::kSent || ev.outcome == interaction::CueOutcome::kSpoken;
          if (!reaches_user || ev.cue.t != e.t) continue;
          // The cue this frame caused: from the frame's arrival to the moment it is handed to the
          // actuator or the speaker.
          const double latency = ms_between(item.arrival, Clock::now());
          latency_ms.push_back(latency);
          latency_csv << fmt::format("{},{:.3f},{},{:.3f}\n", e.t, ns_to_seconds(ev.t - t_origin(e.t)),
                                     interaction::to_string(ev.cue.kind), latency);
        }
      }
    });
    f.times.interaction_ms = ms_between(t2, Clock::now());
    planning_ms.push_back(f.times.planning_ms);
    interaction_ms.push_back(f.times.interaction_ms);
    f.action = std::string(planning::to_string(g.command.action));
    f.reason = std::string(planning::to_string(g.command.reason));
    f.detail = g.command.detail;
    std::lock_guard<std::mutex> lock(m);
    const auto added = options.threaded ? added_frames.end() : added_frames.find(item.frame->t);
    if (added != added_frames.end()) {
      RgbdFrame& done = *added->second;  // mapped and guided on one thread: its images are done with
      done.depth = {};
      done.intensity = {};
      done.labels.reset();
      done.label_confidence.reset();
      done.class_probabilities.reset();
    }
    // The frame's mapping half is logged (map_step ran first); its row is complete. Frames older
    // than it still in the log were mapped but their guidance dropped (real time): not written.
    if (const auto l = log.find(e.t); l != log.end()) {
      f.mapped = l->second.mapped;
      f.times.mapping_ms = l->second.times.mapping_ms;
    }
    log.erase(log.begin(), log.upper_bound(e.t));
    stage_times[e.t] = f.times;
    stages_csv << fmt::format("{},{},{},{:.4f},{:.4f},{:.4f},{},{},{}\n", e.t, f.frame, f.mapped ? 1 : 0,
                              f.times.mapping_ms, f.times.planning_ms, f.times.interaction_ms, f.action, f.reason,
                              csv_field(f.detail));
  }

  /// The timeline's clock starts at the first estimate with a frame (speech.wav's zero).
  Timestamp t_origin(Timestamp t) {
    if (!origin) origin = t;
    return *origin;
  }

  void add_frame(RgbdFrame frame) {
    std::lock_guard<std::mutex> lock(m);
    auto owned = std::make_unique<RgbdFrame>(std::move(frame));
    frame_at[owned->t] = owned.get();
    added_frames[owned->t] = std::move(owned);
  }

  void on_estimate(const StateEstimate& e, Clock::time_point arrival) {
    if (error()) std::rethrow_exception(error());  // stops the estimator: the run ends at the failed stage
    std::map<Timestamp, const RgbdFrame*>::const_iterator it;
    {
      std::lock_guard<std::mutex> lock(m);
      it = frame_at.find(e.t);
    }
    if (it == frame_at.end()) {
      ++without_frame;
      return;
    }
    ++estimates;
    DeviceItem item{e, arrival, it->second, false, 0, nullptr, {}};
    if (!options.threaded) {
      map_step(item);
      guide_step(item);
      return;
    }
    if (options.predict_at_arrival) {
      // The planners have had this frame at its arrival (on_frame_arrival): the solved estimate
      // builds the map and is the next prediction's start.
      {
        std::lock_guard<std::mutex> lock(m);
        last_solved = e;
      }
      map_queue.push(std::move(item));
    } else if (options.drop_when_full) {
      // Real time: the planners do not wait for this frame's map; they take the newest one.
      DeviceItem to_guide = item;
      map_queue.push(std::move(item));
      guide_queue.push(std::move(to_guide));
    } else {
      map_queue.push(std::move(item));  // the map thread hands it on with its map
    }
  }

  void on_frame_arrival(Timestamp t, Clock::time_point arrival) {
    if (error()) std::rethrow_exception(error());
    const auto it = frame_at.find(t);
    std::optional<StateEstimate> from;
    {
      std::lock_guard<std::mutex> lock(m);
      from = last_solved;
    }
    if (it == frame_at.end() || !from || from->t > t) return;  // nothing solved yet: no pose to act on
    DeviceItem item{from->t == t ? *from : estimation::predict_state(*from, t, imu, imu_noise), arrival, it->second,
                    false, 0, nullptr, {}};
    {
      std::lock_guard<std::mutex> lock(m);
      prediction_s.push_back(ns_to_seconds(t - from->t));
    }
    guide_queue.push(std::move(item));  // refused once closed after an error: reported by the next call
  }

  void fail(std::exception_ptr e) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (!first_error) first_error = e;
    }
    map_queue.close(true);
    guide_queue.close(true);
  }
  std::exception_ptr error() {
    std::lock_guard<std::mutex> lock(m);
    return first_error;
  }

  void start_threads() {
    map_thread = std::thread([this] {
      try {
        while (auto item = map_queue.pop()) {
          map_step(*item);
          if (!options.drop_when_full) guide_queue.push(std::move(*item));
        }
        guide_queue.close();
      } catch (...) {
        fail(std::current_exception());
      }
    });
    guide_thread = std::thread([this] {
      try {
        while (auto item = guide_queue.pop()) {
          if (options.drop_when_full) item->snapshot = nullptr;  // the newest map, read now
          guide_step(*item);
        }
      } catch (...) {
        fail(std::current_exception());
      }
    });
  }

  void stop_threads() {
    map_queue.close();
    if (map_thread.joinable()) map_thread.join();
    guide_queue.close();
    if (guide_thread.joinable()) guide_thread.join();
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
  std::map<Timestamp, std::unique_ptr<RgbdFrame>> added_frames;  // add_frame's, guarded by m
  std::ofstream plans_csv, latency_csv, stages_csv;  // written as the frames go
  std::vector<double> mapping_ms, planning_ms, interaction_ms, latency_ms;
  std::size_t estimates = 0, without_frame = 0, plans = 0, plans_found = 0, map_counter = 0;
  std::optional<Timestamp> origin;

  const std::vector<ImuSample>& imu;
  estimation::ImuNoise imu_noise;
  std::optional<StateEstimate> last_solved;  // guarded by m
  std::vector<double> prediction_s, map_latency_ms;
  runtime::BoundedQueue<DeviceItem> map_queue, guide_queue;
  std::thread map_thread, guide_thread;
  std::mutex m;  // guards what both threads touch: newest, pending_events, log, first_error
  std::shared_ptr<const MapSnapshot> newest;
  std::vector<interaction::GuidanceTimelineEntry> pending_events;
  std::map<Timestamp, FrameLog> log;  // frames mapped, their guidance not yet done
  std::map<Timestamp, StageTimes> stage_times;
  interaction::GuidanceTimelineWriter timeline;  // guidance_timeline.csv, as the frames go
  std::exception_ptr first_error;
};

DeviceRun::DeviceRun(const DeviceSpec& spec, const Config& config, const io::Recording& recording,
                     const std::filesystem::path& recording_dir, const CameraCalibration& camera,
                     const std::filesystem::path& out, const MapSessionOptions& map_options,
                     const DeviceRunOptions& options)
    : impl_(std::make_unique<Impl>(spec, config, recording, recording_dir, camera, out, map_options, options)) {
  if (options.threaded) impl_->start_threads();
}

DeviceRun::~DeviceRun() { impl_->stop_threads(); }

void DeviceRun::on_estimate(const StateEstimate& estimate, Clock::time_point arrival) {
  impl_->on_estimate(estimate, arrival);
}

void DeviceRun::on_frame_arrival(Timestamp t, Clock::time_point arrival) { impl_->on_frame_arrival(t, arrival); }

void DeviceRun::add_frame(RgbdFrame frame) { impl_->add_frame(std::move(frame)); }

const std::map<Timestamp, DeviceRun::StageTimes>& DeviceRun::stage_times() const { return impl_->stage_times; }

nlohmann::ordered_json DeviceRun::finish() {
  Impl& d = *impl_;
  d.stop_threads();
  d.session->drain();
  const std::vector<interaction::CueEvent>& events = d.session->events();
  for (auto* f : {&d.plans_csv, &d.latency_csv, &d.stages_csv}) f->flush();
  d.timeline.close();
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
  j["stages"] = {{"mapping", runtime::stage_distribution(d.mapping_ms)},
                 {"planning", runtime::stage_distribution(d.planning_ms)},
                 {"interaction", runtime::stage_distribution(d.interaction_ms)}};
  j["latency"] = runtime::stage_distribution(d.latency_ms);
  j["latency"]["cues"] = d.latency_ms.size();
  j["latency"]["note"] = "wall clock from a sensor frame's arrival to the cue it caused reaching the actuator or speaker";
  j["latency"]["pose"] = d.options.predict_at_arrival ? "the newest solved estimate carried through the IMU to the frame"
                                                      : "the frame's solved estimate";
  if (d.options.predict_at_arrival) {
    std::vector<double> ms;
    for (double v : d.prediction_s) ms.push_back(1e3 * v);
    j["latency"]["prediction_span_ms"] = runtime::stage_distribution(ms);
  }
  // When what a frame shows (obstacles) is in the map the planners read.
  j["map_latency"] = runtime::stage_distribution(d.map_latency_ms);
  j["guidance"] = d.stage->summary();
  j["plans"] = {{"made", d.plans}, {"found", d.plans_found}};
  j["cues"] = {{"timeline_entries", d.timeline.entries()}, {"events", events.size()}, {"outcomes", counts},
               {"spoken", spoken}, {"speech_wav_s", speech_s}};
  j["estimates"] = {{"with_frame", d.estimates}, {"without_frame", d.without_frame}};
  if (d.options.threaded)
    j["device_thread"] = {{"threads", "mapping; planning + interaction"},
                          {"queue_capacity", d.options.queue_capacity},
                          {"when_full", d.options.drop_when_full ? "drop the oldest" : "wait"},
                          {"dropped", d.map_queue.dropped() + d.guide_queue.dropped()},
                          {"dropped_before_mapping", d.map_queue.dropped()},
                          {"dropped_before_planning", d.guide_queue.dropped()},
                          {"max_depth", std::max(d.map_queue.max_depth(), d.guide_queue.max_depth())}};
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
  if (const auto e = d.error()) std::rethrow_exception(e);
  return j;
}

}  // namespace navaid::experiments
