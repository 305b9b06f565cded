#include "navaid/interaction/steering_wheel_adapter.hpp"

#include "navaid/interaction/config_schema.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "adapter_support.hpp"

namespace navaid::interaction {

namespace {


}  // namespace

namespace {
const ConfigKey<double> kSteeringWheelAdapterRefresh{"interaction.wheel.refresh_hz", SteeringWheelConfig{}.refresh_hz, {1.0, 100.0},
                                 "the steering wheel's refresh rate [Hz] (the planner's re-planning rate)"};
const ConfigKey<double> kSteeringWheelAdapterHoldMargin{"interaction.wheel.hold_margin", SteeringWheelConfig{}.hold_margin, {0.01, 1.0},
                                    "a steering command is held for the refresh period times (1 + this)"};
const ConfigKey<double> kMaxSteering{"interaction.wheel.max_steering_deg", SteeringWheelConfig{}.max_steering_deg,
                                     {1.0, 90.0}, "largest commanded steering angle [deg]"};
}  // namespace

ConfigSchema steering_wheel_config_schema() { return ConfigSchema().add(kSteeringWheelAdapterRefresh).add(kSteeringWheelAdapterHoldMargin).add(kMaxSteering); }

SteeringWheelConfig read_steering_wheel_config(const Config& config) {
  SteeringWheelConfig c;
  c.refresh_hz = get(config, kSteeringWheelAdapterRefresh);
  c.hold_margin = get(config, kSteeringWheelAdapterHoldMargin);
  c.max_steering_deg = get(config, kMaxSteering);
  return c;
}

SteeringWheelAdapter::SteeringWheelAdapter(const SteeringWheelConfig& config) : config_(config) {
  detail::require(config_.refresh_hz >= 1.0 && config_.refresh_hz <= 100.0, "wheel: refresh_hz must be in [1, 100]");
  detail::require(config_.hold_margin >= 0.01 && config_.hold_margin <= 1.0, "wheel: hold_margin must be in [0.01, 1]");
  detail::require(config_.max_steering_deg >= 1.0 && config_.max_steering_deg <= 90.0,
                  "wheel: max_steering_deg must be in [1, 90]");
  hold_ms_ = refresh_hold_ms(1.0 / config_.refresh_hz, config_.hold_margin);
}

std::string_view SteeringWheelAdapter::actuator_name(int index) const {
  if (index != kSteering) throw std::out_of_range("wheel: no actuator " + std::to_string(index));
  return "steering";
}

std::optional<ActuatorPattern> SteeringWheelAdapter::pattern(const Cue& cue) const {
  ActuatorPattern p = detail::empty_pattern(cue.t, DeviceKind::kWheel);
  switch (cue.kind) {
    case CueKind::kTurn:
    case CueKind::kVeer:
    case CueKind::kOnCourse: {
      // The PI controller's output; without it (another planner) the walking direction itself.
      const std::optional<double> steer = cue.steering_rad ? cue.steering_rad : cue.direction_rad;
      if (!steer || !std::isfinite(*steer)) return std::nullopt;
      const double limit = config_.max_steering_deg * M_PI / 180.0;
      const double mrad = std::round(std::clamp(*steer, -limit, limit) * 1000.0);
      p.commands.push_back(detail::command(kSteering, static_cast<int>(mrad), 0, 0, hold_ms_));
      return p;
    }
    case CueKind::kStop:
      // Straight ahead, held: the wheel brakes the cane instead of going limp.
      p.commands.push_back(detail::command(kSteering, 0, 0, 0, hold_ms_));
      return p;
    case CueKind::kArrive:
      return p;  // ours: the motor released
    case CueKind::kObstacle:
    case CueKind::kObjectDirection:
    case CueKind::kSystem:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace navaid::interaction
