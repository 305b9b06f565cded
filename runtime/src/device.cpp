#include "navaid/runtime/device.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <thread>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/state_prediction.hpp"
#include "navaid/interaction/cue_session.hpp"
#include "navaid/interaction/device_adapter.hpp"
#include "navaid/runtime/bounded_queue.hpp"
#include "navaid/runtime/estimator_driver.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"
#include "navaid/runtime/guidance_stage.hpp"

namespace navaid::runtime {

namespace {

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
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

/// A new mission or a voice command, for the first estimate at or after t.
struct UserRequest {
  Timestamp t = 0;
  std::optional<DeviceMission> mission;
  std::optional<interaction::VoiceCommand> voice;
};

struct Device::Impl {
  Impl(const DeviceSpec& s, const Config& c, const CameraCalibration& cam, const DeviceMission& first,
       const DeviceOptions& o, DeviceSinks k)
      : spec(s),
        config(c),
        camera(cam),
        mission(first),
        options(o),
        sinks(std::move(k)),
        generator(interaction::read_cue_generator_config(c)),
        policy(interaction::read_cue_policy_config(c)),
        device(interaction::make_device_adapter(s.actuator, c)),
        speech_config(interaction::read_speech_config(c)),
        map(mapping::read_mapper_config(c), cam, o.mapping),
        stage(make_guidance_stage({s, c, cam, first})),
        map_queue(o.queue_capacity, o.drop_when_full),
        guide_queue(o.queue_capacity, o.drop_when_full),
        newest(std::make_shared<MapSnapshot>()) {
    if (spec.speech == "text") speech_config.text_only = true;
    if (spec.speech != "off") speech = std::make_unique<interaction::SynthesizedSpeech>(speech_config);
    session = std::make_unique<interaction::CueSession>(generator, policy, *device, speech.get(), sinks.cue);
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
      if (!item.mapped) return;
      const MappedFrame mapped = map.add(*item.frame, item.estimate);
      for (const auto& c : mapped.network_changes) item.system_events.push_back(network_event(c));
      if (sinks.map) sinks.map(*item.frame, item.estimate, mapped, map);
    });
    item.mapping_ms = ms_between(t0, Clock::now());
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
    std::vector<UserRequest> due;
    {
      std::lock_guard<std::mutex> lock(m);
      if (!snapshot) snapshot = newest;
      entries.swap(pending_events);
      for (; !requests.empty() && requests.front().t <= e.t; requests.pop_front()) due.push_back(std::move(requests.front()));
    }
    DeviceFrameLog f;
    f.t = e.t;
    f.frame = item.frame->index;
    const auto t1 = Clock::now();
    GuidanceOutput g;
    in_stage("planning", item, [&] {
      for (UserRequest& r : due) handle(r, e, entries);
      g = stage->update({*item.frame, e, snapshot->maps ? &*snapshot->maps : nullptr,
                         snapshot->scan ? &*snapshot->scan : nullptr});
    });
    const auto t2 = Clock::now();
    f.times.planning_ms = ms_between(t1, t2);
    if (g.new_plan) {
      if (sinks.plan) sinks.plan(e.t, g.planner, *g.new_plan);
      ++plans;
      plans_found += g.new_plan->found() ? 1 : 0;
    }
    entries.emplace_back(g.command);
    in_stage("interaction", item, [&] {
      for (const auto& entry : entries) {
        ++timeline_entries;
        if (sinks.guidance) sinks.guidance(entry);
        for (const interaction::CueEvent& ev : session->feed(entry)) {
          const bool reaches_user = ev.outcome == interaction::CueOutcome::kSent || ev.outcome == interaction::CueOutcome::kSpoken;
          if (!reaches_user || ev.cue.t != e.t) continue;
          // The cue this frame caused: from the frame's arrival to the moment it is handed to the
          // actuator or the speaker.
          const double latency = ms_between(item.arrival, Clock::now());
          latency_ms.push_back(latency);
          const Timestamp zero = t_origin(e.t);
          if (sinks.latency) sinks.latency({e.t, ev, latency, zero});
        }
      }
    });
    f.times.interaction_ms = ms_between(t2, Clock::now());
    planning_ms.push_back(f.times.planning_ms);
    interaction_ms.push_back(f.times.interaction_ms);
    f.command = g.command;
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
    if (sinks.frame) sinks.frame(f);
  }

  /// What the user asked for, at estimate e: a voice command goes to the cue session (it answers);
  /// a new mission rebuilds the guidance stage.
  void handle(UserRequest& r, const StateEstimate& e, std::vector<interaction::GuidanceTimelineEntry>& entries) {
    if (r.voice) {
      std::string said = interaction::describe(*r.voice);
      if (r.voice->kind == interaction::VoiceCommand::Kind::kGoTo) {
        r.mission = mission.place ? mission.place(r.voice->place, e) : std::nullopt;
        if (!r.mission) said = interaction::describe(interaction::VoiceCommand{});  // a place it does not know
      }
      entries.emplace_back(interaction::SystemEvent{e.t, interaction::SystemEventKind::kVoiceCommand, said});
    }
    if (!r.mission) return;
    earlier_missions.push_back(stage->summary());
    stage = make_guidance_stage({spec, config, camera, *r.mission});
    mission = std::move(*r.mission);
  }

  void request(UserRequest r) {
    std::lock_guard<std::mutex> lock(m);
    // In time order; requests of one time keep the order they were made in.
    const auto at = std::upper_bound(requests.begin(), requests.end(), r.t,
                                     [](Timestamp t, const UserRequest& q) { return t < q.t; });
    requests.insert(at, std::move(r));
  }

  void add(SensorEvent event, Clock::time_point arrival) {
    if (!driver) throw Error("device " + spec.name + ": sensor events need an estimator (Device::set_estimator)");
    if (auto* frame = std::get_if<RgbdFrame>(&event); frame && frame->camera == camera.name) {
      if (!driver->image_input()) return add_frame(std::move(*frame));  // its features stand for it
      add_frame(RgbdFrame(*frame));  // the device maps and plans from it, the front end tracks it
    }
    if (const auto* sample = std::get_if<ImuSample>(&event); sample && options.predict_at_arrival) add_imu(*sample);
    const auto t0 = Clock::now();
    const std::vector<StateEstimate> made = driver->process(std::move(event));
    estimator_s += std::chrono::duration<double>(Clock::now() - t0).count();
    for (const StateEstimate& e : made) on_estimate(e, arrival);
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

  void add_frame(const RgbdFrame* frame) {
    std::lock_guard<std::mutex> lock(m);
    frame_at[frame->t] = frame;
  }

  void add_imu(const ImuSample& s) {
    std::lock_guard<std::mutex> lock(m);
    imu.push_back(s);
  }

  void on_estimate(const StateEstimate& e, Clock::time_point arrival) {
    if (error()) std::rethrow_exception(error());  // stops the estimator: the run ends at the failed stage
    if (sinks.estimate) sinks.estimate(e);
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
    std::optional<StateEstimate> from;
    const RgbdFrame* frame = nullptr;
    std::vector<ImuSample> samples;
    {
      std::lock_guard<std::mutex> lock(m);
      from = last_solved;
      if (const auto it = frame_at.find(t); it != frame_at.end()) frame = it->second;
      if (frame && from && from->t < t) samples = imu_between(from->t, t);
    }
    if (!frame || !from || from->t > t) return;  // nothing solved yet: no pose to act on
    if (from->t < t && (samples.empty() || samples.back().t < t)) return;  // the IMU has not reached the frame yet
    DeviceItem item{from->t == t ? *from : estimation::predict_state(*from, t, samples, options.imu_noise), arrival,
                    frame, false, 0, nullptr, {}};
    {
      std::lock_guard<std::mutex> lock(m);
      prediction_s.push_back(ns_to_seconds(t - from->t));
    }
    guide_queue.push(std::move(item));  // refused once closed after an error: reported by the next call
  }

  /// The IMU samples that carry a state from `from` to `to` (one on each side, for interpolation);
  /// older ones are dropped (the next prediction starts later). Called under m.
  std::vector<ImuSample> imu_between(Timestamp from, Timestamp to) {
    auto first = std::lower_bound(imu.begin(), imu.end(), from, [](const ImuSample& s, Timestamp t) { return s.t < t; });
    if (first != imu.begin()) --first;
    auto last = std::upper_bound(first, imu.end(), to, [](Timestamp t, const ImuSample& s) { return t < s.t; });
    if (last != imu.end()) ++last;
    std::vector<ImuSample> out(first, last);
    imu.erase(imu.begin(), first);
    return out;
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
  Config config;  // a copy: the guidance stage is built anew from it for a new mission (the caller's
                  // ConfigReads notes the first stage's reads, made from the caller's Config)
  CameraCalibration camera;
  DeviceMission mission;     // the current one; guide thread
  DeviceOptions options;
  DeviceSinks sinks;
  interaction::CueGeneratorConfig generator;
  interaction::CuePolicyConfig policy;
  std::unique_ptr<interaction::DeviceAdapter> device;
  interaction::SpeechConfig speech_config;
  std::unique_ptr<interaction::SynthesizedSpeech> speech;
  std::unique_ptr<interaction::CueSession> session;
  MappingStage map;
  std::unique_ptr<GuidanceStage> stage;
  std::vector<nlohmann::ordered_json> earlier_missions;  // the replaced stages' summaries
  std::deque<UserRequest> requests;                      // guarded by m
  std::unique_ptr<EstimatorDriver> driver;               // add()'s
  double estimator_s = 0;
  std::map<Timestamp, const RgbdFrame*> frame_at;                 // guarded by m
  std::map<Timestamp, std::unique_ptr<RgbdFrame>> added_frames;  // add_frame's, guarded by m
  std::vector<double> mapping_ms, planning_ms, interaction_ms, latency_ms;
  std::size_t estimates = 0, without_frame = 0, plans = 0, plans_found = 0, map_counter = 0, timeline_entries = 0;
  std::optional<Timestamp> origin;

  std::vector<ImuSample> imu;                // guarded by m
  std::optional<StateEstimate> last_solved;  // guarded by m
  std::vector<double> prediction_s, map_latency_ms;
  BoundedQueue<DeviceItem> map_queue, guide_queue;
  std::thread map_thread, guide_thread;
  std::mutex m;  // guards what both threads touch: newest, pending_events, log, first_error
  std::shared_ptr<const MapSnapshot> newest;
  std::vector<interaction::GuidanceTimelineEntry> pending_events;
  std::map<Timestamp, DeviceFrameLog> log;  // frames mapped, their guidance not yet done
  std::map<Timestamp, StageTimes> stage_times;
  std::exception_ptr first_error;
};

Device::Device(const DeviceSpec& spec, const Config& config, const CameraCalibration& camera,
               const DeviceMission& mission, const DeviceOptions& options, DeviceSinks sinks)
    : impl_(std::make_unique<Impl>(spec, config, camera, mission, options, std::move(sinks))) {
  if (options.threaded) impl_->start_threads();
}

Device::~Device() { impl_->stop_threads(); }

void Device::on_estimate(const StateEstimate& estimate, Clock::time_point arrival) {
  impl_->on_estimate(estimate, arrival);
}

void Device::on_frame_arrival(Timestamp t, Clock::time_point arrival) { impl_->on_frame_arrival(t, arrival); }

void Device::add_frame(RgbdFrame frame) { impl_->add_frame(std::move(frame)); }
void Device::add_frame(const RgbdFrame* frame) { impl_->add_frame(frame); }
void Device::add_imu(const ImuSample& sample) { impl_->add_imu(sample); }

void Device::set_estimator(std::unique_ptr<EstimatorDriver> estimator) {
  if (!estimator) throw Error("device " + impl_->spec.name + ": no estimator given");
  if (impl_->driver) throw Error("device " + impl_->spec.name + ": it has its estimator already");
  impl_->driver = std::move(estimator);
}
void Device::add(SensorEvent event, Clock::time_point arrival) { impl_->add(std::move(event), arrival); }
const EstimatorDriver& Device::estimator() const {
  if (!impl_->driver) throw Error("device " + impl_->spec.name + ": it has no estimator (Device::set_estimator)");
  return *impl_->driver;
}
double Device::estimator_busy_s() const { return impl_->estimator_s; }

void Device::end_of_input(Clock::time_point arrival) {
  Impl& d = *impl_;
  if (!d.driver) throw Error("device " + d.spec.name + ": it has no estimator (Device::set_estimator)");
  const auto t0 = Clock::now();
  const std::vector<StateEstimate> last = d.driver->finish();
  d.estimator_s += std::chrono::duration<double>(Clock::now() - t0).count();
  for (const StateEstimate& e : last) d.on_estimate(e, arrival);
}

void Device::set_mission(Timestamp t, DeviceMission mission) { impl_->request({t, std::move(mission), std::nullopt}); }
void Device::on_voice_command(Timestamp t, const interaction::VoiceCommand& command) {
  impl_->request({t, std::nullopt, command});
}

const std::map<Timestamp, StageTimes>& Device::stage_times() const { return impl_->stage_times; }
const MappingStage& Device::mapping() const { return impl_->map; }
const interaction::SynthesizedSpeech* Device::speech() const { return impl_->speech.get(); }
const interaction::DeviceAdapter& Device::actuator() const { return *impl_->device; }

DeviceResult Device::finish() {
  Impl& d = *impl_;
  d.stop_threads();
  d.session->drain();
  const std::vector<interaction::CueEvent>& events = d.session->events();
  std::vector<std::string> spoken;
  for (const auto& e : events)
    if (e.outcome == interaction::CueOutcome::kSpoken) spoken.push_back(e.text);
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
  j["latency"]["pose"] = d.options.predict_at_arrival ? "the newest solved estimate carried through the IMU to the frame"
                                                      : "the frame's solved estimate";
  if (d.options.predict_at_arrival) {
    std::vector<double> ms;
    for (double v : d.prediction_s) ms.push_back(1e3 * v);
    j["latency"]["prediction_span_ms"] = stage_distribution(ms);
  }
  // When what a frame shows (obstacles) is in the map the planners read.
  j["map_latency"] = stage_distribution(d.map_latency_ms);
  j["guidance"] = d.stage->summary();
  if (!d.earlier_missions.empty()) j["guidance"]["earlier_missions"] = d.earlier_missions;
  j["plans"] = {{"made", d.plans}, {"found", d.plans_found}};
  j["cues"] = {{"timeline_entries", d.timeline_entries}, {"events", events.size()}, {"outcomes", counts},
               {"spoken", spoken}};
  j["estimates"] = {{"with_frame", d.estimates}, {"without_frame", d.without_frame}};
  if (d.options.threaded)
    j["device_thread"] = {{"threads", "mapping; planning + interaction"},
                          {"queue_capacity", d.options.queue_capacity},
                          {"when_full", d.options.drop_when_full ? "drop the oldest" : "wait"},
                          {"dropped", d.map_queue.dropped() + d.guide_queue.dropped()},
                          {"dropped_before_mapping", d.map_queue.dropped()},
                          {"dropped_before_planning", d.guide_queue.dropped()},
                          {"max_depth", std::max(d.map_queue.max_depth(), d.guide_queue.max_depth())}};
  return {std::move(j), events, d.origin, d.error()};
}

}  // namespace navaid::runtime
