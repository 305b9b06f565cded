// navaid run --realtime: the front end (image loading + tracking) on a thread of its own hands
// FeatureFrames through a bounded queue to the estimator, which runs on the calling thread and
// merges them with the recording's IMU / GPS / magnetometer events in time order
// (docs/estimator.md, "navaid run").
//
// Ordering. The front end publishes `next_frame_t`, the time of the next frame it has not handed
// over yet: every frame before it is queued, consumed or dropped. The estimator takes an IMU /
// GPS / mag event at t only when t <= next_frame_t (at equal times those precede the frame, as in
// io::SensorEventStream), and a queued frame only when it is older than its next such event, so it
// sees exactly replay's order and never runs ahead of the front end.
//
// Both threads go through one EstimatorDriver: the front end's thread calls track(), the
// estimator's estimate(). Gyro bias: with frontend.imu_prediction the KLT prediction of frame k
// uses the back end's bias after every event before frame k (replay's data flow), so the front end
// waits for the estimator to get there before tracking (the driver hands the newest bias over);
// image loading overlaps with the estimator's work. Without the prediction the front end runs
// ahead up to the queue's capacity.
//
// Dropping (speed > 0 only). Frames arrive at start + (t - t0) / speed. A frame the front end takes
// up after the next one has arrived is skipped (stale); a tracked frame that finds the queue full
// pushes out the oldest queued one. Either way the newest frames are processed, in order. At speed
// 0 nothing is dropped (the front end waits for room) and the estimates equal replay's bit for bit.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <thread>

#include "navaid/core/errors.hpp"
#include "navaid/io/event_stream.hpp"
#include "navaid/runtime/estimator_pipeline.hpp"

namespace navaid::runtime {
namespace {

using Clock = std::chrono::steady_clock;
constexpr Timestamp kNever = std::numeric_limits<Timestamp>::max();

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct QueuedFrame {
  FeatureFrame features;
  std::optional<FrontendTime> frontend;
  Clock::time_point arrival;
};

// Everything the two threads share, under one mutex.
struct Shared {
  std::mutex m;
  std::condition_variable changed;
  std::deque<QueuedFrame> queue;
  Timestamp next_frame_t = kNever;      // frames before it are queued, consumed or dropped
  std::size_t frames_outstanding = 0;   // handed over, neither dropped nor estimated yet
  Timestamp estimator_next_t = kNever;  // the estimator's next unprocessed IMU / GPS / mag event
  bool abort = false;
  std::size_t dropped_full_queue = 0, max_depth = 0;
};

nlohmann::ordered_json distribution(const std::vector<double>& v) {
  return {{"median", percentile(v, 0.5)}, {"p99", percentile(v, 0.99)},
          {"max", v.empty() ? 0.0 : *std::max_element(v.begin(), v.end())}};
}

class FrontEndThread {
 public:
  FrontEndThread(const PipelineInput& in, const RealtimeOptions& options, Shared& shared, Clock::time_point start)
      : in_(in), options_(options), shared_(shared), start_(start) {
    if (in.driver.image_input()) {
      for (std::size_t i = 0; i < in.recording.frames.size(); ++i)
        if (in.recording.frames[i].camera == in.camera) frames_.push_back(i);
      for (auto i : frames_) times_.push_back(in.recording.frames[i].t);
    } else {
      for (const auto& f : in.recording.features) times_.push_back(f.t);  // replay hands over every one
    }
  }

  Timestamp first_frame_t() const { return times_.empty() ? kNever : times_.front(); }

  void run() {
    try {
      for (std::size_t k = 0; k < times_.size(); ++k) {
        if (!handle(k)) break;
      }
    } catch (...) {
      error_ = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(shared_.m);
    shared_.next_frame_t = kNever;
    if (error_) shared_.abort = true;
    shared_.changed.notify_all();
  }

  std::exception_ptr error() const { return error_; }

  nlohmann::ordered_json statistics() const {
    nlohmann::ordered_json j;
    j["frames_in"] = times_.size();
    j["frames_handed_over"] = handed_over_;
    j["skipped_stale"] = skipped_;
    j["busy_s"] = busy_ms_ / 1000.0;
    if (in_.driver.image_input()) {
      j["track_ms"] = distribution(track_ms_);
      j["image_load_ms"] = distribution(load_ms_);
    }
    j["waiting_s"] = {{"for_arrival", pacing_ms_ / 1000.0},
                      {"for_gyro_bias", bias_wait_ms_ / 1000.0},
                      {"for_queue_room", queue_wait_ms_ / 1000.0}};
    return j;
  }

 private:
  Clock::time_point arrival_of(std::size_t k) const {
    const double s = ns_to_seconds(times_[k] - times_.front()) / options_.speed;
    return start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  Timestamp next_time(std::size_t k) const { return k + 1 < times_.size() ? times_[k + 1] : kNever; }

  // Returns false when the run was aborted.
  bool handle(std::size_t k) {
    const Timestamp t = times_[k];
    QueuedFrame q;
    q.arrival = Clock::now();
    if (options_.speed > 0) {
      const auto wait_start = Clock::now();
      std::this_thread::sleep_until(arrival_of(k));
      pacing_ms_ += ms_since(wait_start);
      q.arrival = arrival_of(k);  // the camera delivered it then, however late the front end is
      if (k + 1 < times_.size() && Clock::now() >= arrival_of(k + 1)) {
        ++skipped_;
        std::lock_guard<std::mutex> lock(shared_.m);
        shared_.next_frame_t = next_time(k);
        shared_.changed.notify_all();
        return !shared_.abort;
      }
    }
    if (in_.on_frame_arrival) in_.on_frame_arrival(t, q.arrival);
    if (in_.driver.image_input()) {
      if (!track(k, t, q)) return false;
    } else {
      q.features = in_.recording.features[k];
    }
    return push(std::move(q), next_time(k));
  }

  bool track(std::size_t k, Timestamp t, QueuedFrame& q) {
    RgbdFrame frame = in_.recording.frames[frames_[k]];
    const auto load_start = Clock::now();
    in_.load_images(frame);
    const double load_ms = ms_since(load_start);
    // The IMU samples replay's source would have seen before this frame (equal stamps first).
    for (; imu_next_ < in_.recording.imu.size() && in_.recording.imu[imu_next_].t <= t; ++imu_next_)
      in_.driver.add_frontend_imu(in_.recording.imu[imu_next_]);
    if (in_.imu_prediction) {
      const auto wait_start = Clock::now();
      std::unique_lock<std::mutex> lock(shared_.m);
      shared_.changed.wait(lock, [&] {
        return shared_.abort || (shared_.frames_outstanding == 0 && shared_.estimator_next_t > t);
      });
      bias_wait_ms_ += ms_since(wait_start);
      if (shared_.abort) return false;
    }
    // The driver tracks with the back end's latest gyro bias (with the prediction, the one after
    // every event before this frame: the wait above).
    q.features = in_.driver.track(std::move(frame));  // other cameras' frames are filtered above
    if (in_.on_tracked) in_.on_tracked(q.features);
    q.frontend = FrontendTime{in_.driver.frontend_source().stats().ms_total, load_ms};
    track_ms_.push_back(q.frontend->track_ms);
    load_ms_.push_back(load_ms);
    busy_ms_ += q.frontend->track_ms + load_ms;
    return true;
  }

  bool push(QueuedFrame q, Timestamp next_t) {
    const auto wait_start = Clock::now();
    std::unique_lock<std::mutex> lock(shared_.m);
    if (options_.speed > 0) {
      if (shared_.queue.size() >= options_.queue_capacity) {
        shared_.queue.pop_front();  // the estimator is behind: the newest frames matter
        --shared_.frames_outstanding;
        ++shared_.dropped_full_queue;
      }
    } else {
      shared_.changed.wait(lock, [&] { return shared_.abort || shared_.queue.size() < options_.queue_capacity; });
      queue_wait_ms_ += ms_since(wait_start);
    }
    if (shared_.abort) return false;
    shared_.queue.push_back(std::move(q));
    ++shared_.frames_outstanding;
    ++handed_over_;
    shared_.max_depth = std::max(shared_.max_depth, shared_.queue.size());
    shared_.next_frame_t = next_t;
    shared_.changed.notify_all();
    return true;
  }

  const PipelineInput& in_;
  const RealtimeOptions& options_;
  Shared& shared_;
  Clock::time_point start_;
  std::vector<std::size_t> frames_;  // indices into recording.frames (image input)
  std::vector<Timestamp> times_;
  std::size_t imu_next_ = 0;
  std::exception_ptr error_;
  std::size_t handed_over_ = 0, skipped_ = 0;
  double busy_ms_ = 0, pacing_ms_ = 0, bias_wait_ms_ = 0, queue_wait_ms_ = 0;
  std::vector<double> track_ms_, load_ms_;
};

// Joins the front end on every way out of the estimator loop, errors included.
class JoinGuard {
 public:
  JoinGuard(std::thread& thread, Shared& shared) : thread_(thread), shared_(shared) {}
  ~JoinGuard() {
    if (!thread_.joinable()) return;
    {
      std::lock_guard<std::mutex> lock(shared_.m);
      shared_.abort = true;
      shared_.changed.notify_all();
    }
    thread_.join();
  }
  JoinGuard(const JoinGuard&) = delete;
  JoinGuard& operator=(const JoinGuard&) = delete;

 private:
  std::thread& thread_;
  Shared& shared_;
};

}  // namespace

void validate(const RealtimeOptions& options) {
  if (!(options.speed >= 0) || !std::isfinite(options.speed))
    throw UsageError("--realtime-speed must be 0 (as fast as possible) or a positive factor, got " +
                      std::to_string(options.speed));
  if (options.queue_capacity < 1) throw UsageError("--realtime-queue must be at least 1");
}

PipelineResult realtime_pipeline(const PipelineInput& in, const RealtimeOptions& options) {
  validate(options);
  if (!in.on_record) throw Error("real-time pipeline: on_record is required");
  if (in.driver.image_input() && !in.load_images) throw Error("real-time pipeline: image input needs an image loader");

  const auto run_start = Clock::now();
  Shared shared;
  FrontEndThread front_end(in, options, shared, run_start);
  shared.next_frame_t = front_end.first_frame_t();

  io::SensorEventStream stream(in.recording);
  const auto next_sensor_event = [&stream]() -> std::optional<SensorEvent> {
    while (auto e = stream.next())
      if (!std::holds_alternative<RgbdFrame>(*e) && !std::holds_alternative<FeatureFrame>(*e)) return e;
    return std::nullopt;
  };
  std::optional<SensorEvent> pending = next_sensor_event();
  shared.estimator_next_t = pending ? event_time(*pending) : kNever;

  PipelineResult result;
  std::map<Timestamp, QueuedFrame> in_flight;  // frames estimated, their estimate not out yet
  std::vector<double> estimator_ms, latency_ms;
  double busy_ms = 0, wait_ms = 0, pending_ms = 0;

  std::thread thread([&front_end] { front_end.run(); });
  {
    JoinGuard guard(thread, shared);
    for (;;) {
      std::optional<QueuedFrame> frame;
      {
        const Timestamp t_event = pending ? event_time(*pending) : kNever;
        const auto wait_start = Clock::now();
        std::unique_lock<std::mutex> lock(shared.m);
        shared.changed.wait(lock,
                            [&] { return shared.abort || !shared.queue.empty() || t_event <= shared.next_frame_t; });
        wait_ms += ms_since(wait_start);
        if (shared.abort) break;
        if (!shared.queue.empty() && shared.queue.front().features.t < t_event) {
          frame = std::move(shared.queue.front());
          shared.queue.pop_front();
          shared.changed.notify_all();  // room in the queue
        } else if (!pending) {
          break;  // no frame to come, no event left
        }
      }
      const auto start = Clock::now();
      std::vector<StateEstimate> out;
      if (frame) {
        out = in.driver.estimate(frame->features);
        in_flight.emplace(frame->features.t, std::move(*frame));
      } else {
        out = in.driver.estimate(*pending);
        pending = next_sensor_event();
      }
      const double ms = ms_since(start);
      busy_ms += ms;
      pending_ms += ms;
      {
        std::lock_guard<std::mutex> lock(shared.m);
        if (frame) --shared.frames_outstanding;
        shared.estimator_next_t = pending ? event_time(*pending) : kNever;
        shared.changed.notify_all();
      }
      if (out.empty()) continue;
      const auto now = Clock::now();
      const std::vector<estimation::FrameStageTimes>& stages = in.driver.stage_times();
      for (std::size_t i = 0; i < out.size(); ++i) {
        auto& e = out[i];
        FrameRecord r;
        r.stages = stages.at(i);  // one per estimate
        r.estimator_ms = pending_ms / static_cast<double>(out.size());
        r.ms = *r.estimator_ms;
        Clock::time_point arrival = now;
        if (const auto it = in_flight.find(e.t); it != in_flight.end()) {
          arrival = it->second.arrival;
          r.frontend = it->second.frontend;
          if (r.frontend) r.ms += r.frontend->track_ms + r.frontend->load_ms;
          r.latency_ms = std::chrono::duration<double, std::milli>(now - it->second.arrival).count();
          in_flight.erase(it);
        }
        // Estimates come in time order: a frame older than this one that is still here made none
        // (the estimator skipped it); dropping it keeps a long run's memory flat.
        in_flight.erase(in_flight.begin(), in_flight.lower_bound(e.t));
        estimator_ms.push_back(*r.estimator_ms);
        if (r.latency_ms) latency_ms.push_back(*r.latency_ms);
        r.estimate = std::move(e);
        in.on_record(r);
        ++result.frames;
        if (in.on_estimate) in.on_estimate(r.estimate, arrival);
      }
      pending_ms = 0;
      if (in.on_progress) in.on_progress(result.frames);
    }
  }  // joined
  if (const auto error = front_end.error()) std::rethrow_exception(error);

  for (auto& e : in.driver.finish()) {
    FrameRecord r;
    if (const auto it = in_flight.find(e.t); it != in_flight.end()) r.frontend = it->second.frontend;
    r.estimate = std::move(e);
    in.on_record(r);
    ++result.frames;
    if (in.on_estimate) in.on_estimate(r.estimate, Clock::now());
  }
  result.wall_s = std::chrono::duration<double>(Clock::now() - run_start).count();

  nlohmann::ordered_json j;
  j["speed"] = options.speed;
  j["queue_capacity"] = options.queue_capacity;
  j["queue_max_depth"] = shared.max_depth;
  j["dropped_full_queue"] = shared.dropped_full_queue;
  j["frontend_thread"] = front_end.statistics();
  j["frames_dropped"] = shared.dropped_full_queue + j["frontend_thread"]["skipped_stale"].get<std::size_t>();
  j["estimator_thread"] = {{"busy_s", busy_ms / 1000.0}, {"waiting_s", wait_ms / 1000.0},
                           {"ms_per_frame", distribution(estimator_ms)}};
  j["latency_ms"] = distribution(latency_ms);
  result.realtime = std::move(j);
  return result;
}

}  // namespace navaid::runtime
