#pragma once
// The Smart Cane's kinesthetic wheel (seed smart-cane-biped-walking-path-generation, §III-A/D):
// an omnidirectional wheel and motor driven by an STM32 over a serial port from the PI heading
// controller (eq. 1), at the planner's 10 Hz. One actuator, index 0 "steering"; its level is the
// steering angle in milliradians, positive to the left.
//
// Walking cues (turn, veer, on course) carry the PI output in cue.steering_rad; a cue without it
// (a planner other than the Smart Cane's) steers by cue.direction_rad instead, ours. Either is
// clamped to +-max_steering_deg. Stop commands level 0 (the wheel brakes straight, held like any
// refreshed command). Ours: arrival releases the motor (all off: nothing left to steer);
// obstacles (the planner's steering already goes around them), object direction and system cues
// have no wheel pattern.
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction {

struct SteeringWheelConfig {
  double refresh_hz = 10.0;        ///< the planner's replanning rate
  double hold_margin = 0.25;       ///< hold = period x (1 + margin)
  double max_steering_deg = 45.0;  ///< |commanded angle| <= this
};

/// Keys interaction.wheel.refresh_hz in [1, 100], .hold_margin in [0.01, 1],
/// .max_steering_deg in [1, 90].
SteeringWheelConfig read_steering_wheel_config(const Config& config);

class SteeringWheelAdapter final : public DeviceAdapter {
 public:
  static constexpr int kSteering = 0;
  static constexpr int kCount = 1;

  /// Throws std::invalid_argument on a config read_steering_wheel_config would reject.
  explicit SteeringWheelAdapter(const SteeringWheelConfig& config = {});

  DeviceKind kind() const override { return DeviceKind::kWheel; }
  std::optional<ActuatorPattern> pattern(const Cue& cue) const override;
  double refresh_period_s() const override { return 1.0 / config_.refresh_hz; }
  int actuator_count() const override { return kCount; }
  std::string_view actuator_name(int index) const override;
  const SteeringWheelConfig& config() const { return config_; }

 private:
  SteeringWheelConfig config_;
  std::uint16_t hold_ms_;
};

}  // namespace navaid::interaction
