#pragma once
// The one place where sensor events enter the front end and the estimator. Replay (navaid run),
// the real-time pipeline (its front-end and estimator threads) and closed-loop trials all feed
// events through an EstimatorDriver, so a fix to how events reach the estimator (ordering, the
// front end's gyro-bias feedback, which frames the features stand for) is made once.
//
// Two halves, because real time runs them on two threads:
//  - the front end (image input only): IMU samples for the KLT prediction, camera frames tracked
//    into FeatureFrames with the back end's latest gyro bias;
//  - the estimator: every other event and the tracked frames, in time order.
// process() runs both halves on the calling thread (replay, closed loop).
#include <mutex>
#include <optional>
#include <vector>

#include "navaid/core/messages.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/estimation/frontend/image_feature_source.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"

namespace navaid::runtime {

class EstimatorDriver {
 public:
  /// Feature input: the events carry FeatureFrames (a recording's features, a simulated rig's).
  explicit EstimatorDriver(estimation::SlidingWindowEstimator estimator);
  /// Image input: camera frames are tracked into features by `source` first.
  EstimatorDriver(estimation::SlidingWindowEstimator estimator, estimation::ImageFeatureSource source);
  EstimatorDriver(const EstimatorDriver&) = delete;
  EstimatorDriver& operator=(const EstimatorDriver&) = delete;

  bool image_input() const { return source_.has_value(); }

  /// Both halves on this thread, in time order: the estimates this event completed.
  std::vector<StateEstimate> process(SensorEvent event);

  /// Front end: what the estimator should get for `event`. Image input: IMU samples also feed the
  /// KLT prediction, a camera frame becomes its FeatureFrame (nothing for another camera's).
  /// Feature input: camera frames are dropped (the recording's features stand for them).
  std::optional<SensorEvent> frontend(SensorEvent event);
  /// Front end, image input only: an IMU sample for the KLT prediction.
  void add_frontend_imu(const ImuSample& sample);
  /// Front end, image input only: the frame tracked with the back end's latest gyro bias. Error
  /// for a frame of another camera or on feature input.
  FeatureFrame track(RgbdFrame frame);

  /// Estimator: one event (a tracked frame or an IMU / GNSS / magnetometer event) in time order.
  std::vector<StateEstimate> estimate(const SensorEvent& event);
  /// The estimates still pending at the end of the input.
  std::vector<StateEstimate> finish();
  /// One per estimate of the last estimate() / process() / finish() call, in the same order.
  const std::vector<estimation::FrameStageTimes>& stage_times() const { return estimator_.stage_times(); }

  const estimation::SlidingWindowEstimator& estimator() const { return estimator_; }
  /// The image front end (its statistics belong to the front end's thread while a run goes).
  /// Error on feature input.
  const estimation::ImageFeatureSource& frontend_source() const;

 private:
  void apply_gyro_bias();

  estimation::SlidingWindowEstimator estimator_;
  std::optional<estimation::ImageFeatureSource> source_;
  std::mutex bias_m_;  // the estimator's thread writes the bias, the front end's reads it
  std::optional<Vec3> gyro_bias_;
};

/// The gyro bias the front end's KLT prediction takes from new estimates: the back end's, once it
/// has one worth using (not while initializing or lost).
std::optional<Vec3> gyro_bias_feedback(const std::vector<StateEstimate>& new_estimates);

}  // namespace navaid::runtime
