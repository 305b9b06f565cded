#include "navaid/runtime/estimator_driver.hpp"

#include "navaid/core/errors.hpp"

namespace navaid::runtime {

EstimatorDriver::EstimatorDriver(estimation::SlidingWindowEstimator estimator) : estimator_(std::move(estimator)) {}

EstimatorDriver::EstimatorDriver(estimation::SlidingWindowEstimator estimator, estimation::ImageFeatureSource source)
    : estimator_(std::move(estimator)), source_(std::move(source)) {}

std::vector<StateEstimate> EstimatorDriver::process(SensorEvent event) {
  std::optional<SensorEvent> input = frontend(std::move(event));
  if (!input) return {};
  return estimate(*input);
}

std::optional<SensorEvent> EstimatorDriver::frontend(SensorEvent event) {
  if (!source_) {
    if (std::holds_alternative<RgbdFrame>(event)) return std::nullopt;
    return event;
  }
  if (std::holds_alternative<RgbdFrame>(event)) apply_gyro_bias();
  return source_->process(std::move(event));
}

void EstimatorDriver::add_frontend_imu(const ImuSample& sample) {
  if (!source_) throw Error("estimator driver: IMU for a front end on feature input");
  source_->add_imu(sample);
}

FeatureFrame EstimatorDriver::track(RgbdFrame frame) {
  if (!source_) throw Error("estimator driver: a camera frame to track on feature input");
  apply_gyro_bias();
  auto features = source_->track(std::move(frame));
  if (!features) throw Error("estimator driver: a frame of another camera than the front end's");
  return std::move(*features);
}

std::vector<StateEstimate> EstimatorDriver::estimate(const SensorEvent& event) {
  std::vector<StateEstimate> out = estimator_.process(event);
  if (source_) {
    if (auto b_g = gyro_bias_feedback(out)) {
      std::lock_guard<std::mutex> lock(bias_m_);
      gyro_bias_ = *b_g;
    }
  }
  return out;
}

std::vector<StateEstimate> EstimatorDriver::finish() { return estimator_.finish(); }

const estimation::ImageFeatureSource& EstimatorDriver::frontend_source() const {
  if (!source_) throw Error("estimator driver: no image front end on feature input");
  return *source_;
}

void EstimatorDriver::apply_gyro_bias() {
  std::lock_guard<std::mutex> lock(bias_m_);
  if (gyro_bias_) source_->set_gyro_bias(*gyro_bias_);
}

std::optional<Vec3> gyro_bias_feedback(const std::vector<StateEstimate>& new_estimates) {
  if (new_estimates.empty()) return std::nullopt;
  const EstimatorMode mode = new_estimates.back().mode;
  if (mode == EstimatorMode::kInitializing || mode == EstimatorMode::kLost) return std::nullopt;
  return new_estimates.back().b_g;
}

}  // namespace navaid::runtime
