#pragma once
// How navaid run drives the estimator over a recording: deterministic single-threaded replay
// (replay_pipeline.cpp, the default) or the real-time pipeline with the front end and the
// estimator on their own threads (realtime_pipeline.cpp, --realtime). Both hand one FrameRecord
// per estimate, in output order, to PipelineInput::on_record and keep none: a run's history is
// its caller's to stream or keep (an hour-long walk makes ~100 000 of them).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "navaid/core/state_estimate.hpp"
#include "navaid/io/recording.hpp"
#include "navaid/runtime/estimator_driver.hpp"

namespace navaid::runtime {

struct FrontendTime {
  double track_ms = 0, load_ms = 0;
};

struct FrameRecord {
  StateEstimate estimate;
  /// Work attributed to this frame [ms]: replay, all event handling since the previous estimate
  /// (loading and tracking included); real time, the estimator thread's share plus the front
  /// end's load and track time of this frame (the same work, done on two threads).
  double ms = 0;
  std::optional<FrontendTime> frontend;  ///< image input only
  std::optional<double> estimator_ms;    ///< real time: the estimator thread's share of `ms`
  std::optional<double> latency_ms;      ///< real time: from the frame's arrival to its estimate
  estimation::FrameStageTimes stages;    ///< the estimator's share by stage
};

struct PipelineInput {
  const io::Recording& recording;
  const std::string& camera;  ///< the estimator's camera
  /// Where the events enter the front end and the estimator; image input when it has a front end,
  /// else the recording's features feed the estimator.
  EstimatorDriver& driver;
  /// Fills a frame's intensity (and depth) before tracking.
  estimation::ImageFeatureSource::ImageLoader load_images;
  bool imu_prediction = false;  ///< the front end's KLT prediction uses the back end's gyro bias
  /// Called with the number of records made so far, after each batch (e.g. a progress bar).
  std::function<void(std::size_t)> on_progress;
  /// Called with every frame's record as it is made, before on_estimate (replay: on the one
  /// thread; real time: on the estimator's thread). Required.
  std::function<void(const FrameRecord&)> on_record;
  /// Called with every estimate as it is made (replay: in order on the one thread; real time: on
  /// the estimator's thread, after the estimate's latency is taken), e.g. to map as the run goes,
  /// with the wall-clock time the estimate's camera frame arrived (its loading and tracking
  /// included).
  std::function<void(const StateEstimate&, std::chrono::steady_clock::time_point)> on_estimate;
  /// Real time only: called on the front end's thread when a camera frame of the estimator's
  /// camera arrives (its time, the wall clock), before it is loaded and tracked.
  std::function<void(Timestamp, std::chrono::steady_clock::time_point)> on_frame_arrival;
  /// Image input: called with every frame the front end tracked, as the estimator gets it (replay:
  /// in order on the one thread; real time: in order on the front end's thread), e.g. to save the
  /// tracks as a feature-level recording.
  std::function<void(const FeatureFrame&)> on_tracked;
};

struct RealtimeOptions {
  /// Recording seconds per wall-clock second at which frames arrive; 0 = as fast as possible
  /// (the front end then waits for room in the queue instead of dropping).
  double speed = 0;
  std::size_t queue_capacity = 4;  ///< tracked frames waiting for the estimator
};

struct PipelineResult {
  std::size_t frames = 0;  ///< records handed to on_record
  double wall_s = 0;  ///< from the first event to the last estimate
  /// Real time only: per-thread timing, latency, drops (null in replay).
  nlohmann::ordered_json realtime;
};

/// UsageError naming the option (--realtime-speed, --realtime-queue) when it is unusable.
void validate(const RealtimeOptions& options);

/// Error when on_record is missing.
PipelineResult replay_pipeline(const PipelineInput& in);
/// Error when options are unusable (or on_record is missing); an error on either thread ends the
/// run and is rethrown here.
PipelineResult realtime_pipeline(const PipelineInput& in, const RealtimeOptions& options);

/// Linear-interpolated percentile p in [0, 1] (0 for an empty set).
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double idx = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(idx));
  const auto hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (idx - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// One stage's cost over a run: median, p99 and max per frame [ms], the total [s] and the count.
inline nlohmann::ordered_json stage_distribution(const std::vector<double>& ms) {
  double total = 0;
  for (double v : ms) total += v;
  return {{"median_ms", percentile(ms, 0.5)},
          {"p99_ms", percentile(ms, 0.99)},
          {"max_ms", ms.empty() ? 0.0 : *std::max_element(ms.begin(), ms.end())},
          {"total_s", total / 1000.0},
          {"frames", ms.size()}};
}

}  // namespace navaid::runtime
