// navaid run's default: one thread replays the recording's events in time order through the front
// end (image input) and the estimator; the same recording and configuration give the same
// estimates bit for bit.
#include <chrono>
#include <map>

#include "navaid/core/errors.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"

namespace navaid::runtime {

PipelineResult replay_pipeline(const PipelineInput& in) {
  using Clock = std::chrono::steady_clock;
  if (!in.on_record) throw Error("replay pipeline: on_record is required");
  const auto run_start = Clock::now();
  PipelineResult result;
  std::map<Timestamp, FrontendTime> frontend_pending;  // tracked frames waiting for their estimate
  const auto take_frontend_time = [&](Timestamp t) {
    std::optional<FrontendTime> ft;
    if (const auto it = frontend_pending.find(t); it != frontend_pending.end()) ft = it->second;
    // Estimates come in time order: older frames still here made none (the estimator skipped them).
    frontend_pending.erase(frontend_pending.begin(), frontend_pending.upper_bound(t));
    return ft;
  };
  io::SensorEventStream stream(in.recording);
  EstimatorDriver& driver = in.driver;
  double pending_ms = 0;
  // When the event that completed the pending estimates arrived: a camera frame's, for the
  // frame-to-cue latency (its loading and tracking count).
  Clock::time_point pending_arrival = run_start;
  while (auto event = stream.next()) {
    if (!driver.image_input() && std::holds_alternative<RgbdFrame>(*event)) continue;  // the features stand for the images
    const auto start = Clock::now();
    if (std::holds_alternative<RgbdFrame>(*event) || std::holds_alternative<FeatureFrame>(*event)) pending_arrival = start;
    const bool is_frame = std::holds_alternative<RgbdFrame>(*event);
    const std::optional<SensorEvent> input_event = driver.frontend(std::move(*event));
    if (is_frame && input_event) {
      const estimation::ImageFeatureSource& source = driver.frontend_source();
      frontend_pending[event_time(*input_event)] = {source.stats().ms_total, source.last_load_ms()};
      if (in.on_tracked) in.on_tracked(std::get<FeatureFrame>(*input_event));
    }
    std::vector<StateEstimate> out;
    if (input_event) out = driver.estimate(*input_event);
    pending_ms += std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (out.empty()) continue;
    // The work since the previous estimate (IMU buffering, image loading and tracking included) is
    // this frame's cost.
    const std::vector<estimation::FrameStageTimes>& stages = driver.stage_times();
    for (std::size_t i = 0; i < out.size(); ++i) {
      auto& e = out[i];
      FrameRecord r;
      r.ms = pending_ms / static_cast<double>(out.size());
      r.stages = stages.at(i);  // one per estimate
      r.frontend = take_frontend_time(e.t);
      r.estimate = std::move(e);
      in.on_record(r);
      ++result.frames;
      if (in.on_estimate) in.on_estimate(r.estimate, pending_arrival);
    }
    pending_ms = 0;
    if (in.on_progress) in.on_progress(result.frames);
  }
  for (auto& e : driver.finish()) {
    FrameRecord r;
    r.frontend = take_frontend_time(e.t);
    r.estimate = std::move(e);
    in.on_record(r);
    ++result.frames;
    if (in.on_estimate) in.on_estimate(r.estimate, Clock::now());
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - run_start).count();
  return result;
}

}  // namespace navaid::runtime
