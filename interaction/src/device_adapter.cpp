#include "navaid/interaction/device_adapter.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/interaction/hand_unit_adapter.hpp"
#include "navaid/interaction/rumble_adapter.hpp"
#include "navaid/interaction/steering_wheel_adapter.hpp"

namespace navaid::interaction {

ActuatorPattern DeviceAdapter::all_off(Timestamp t) const {
  ActuatorPattern p;
  p.t = t;
  p.device = kind();
  return p;  // no commands: every actuator off
}

std::uint16_t refresh_hold_ms(double period_s, double margin) {
  if (!(period_s > 0.0) || !(margin > 0.0)) {
    throw std::invalid_argument("refresh_hold_ms: period and margin must be positive");
  }
  // Rounded up (ignoring binary noise: 0.05 s x 1.5 is 75 ms, not 76) and at least 1 ms over
  // the period, so the hold exceeds the period even when period x margin is below 1 ms.
  const double period_ms = period_s * 1000.0;
  const double ms = std::max(std::ceil(period_ms * (1.0 + margin) - 1e-6), std::floor(period_ms + 1e-6) + 1.0);
  if (!(ms <= 65535.0)) {
    throw std::invalid_argument("refresh_hold_ms: hold of " + std::to_string(ms) + " ms exceeds 65535 ms");
  }
  return static_cast<std::uint16_t>(ms);
}

ConfigSchema device_adapter_schema(DeviceKind kind) {
  switch (kind) {
    case DeviceKind::kBelt: return belt_config_schema();
    case DeviceKind::kHand: return hand_unit_config_schema();
    case DeviceKind::kRumble: return rumble_config_schema();
    case DeviceKind::kWheel: return steering_wheel_config_schema();
  }
  return {};
}

std::unique_ptr<DeviceAdapter> make_device_adapter(DeviceKind kind, const Config& config) {
  switch (kind) {
    case DeviceKind::kBelt: return std::make_unique<BeltAdapter>(read_belt_config(config));
    case DeviceKind::kHand: return std::make_unique<HandUnitAdapter>(read_hand_unit_config(config));
    case DeviceKind::kRumble: return std::make_unique<RumbleAdapter>(read_rumble_config(config));
    case DeviceKind::kWheel: return std::make_unique<SteeringWheelAdapter>(read_steering_wheel_config(config));
  }
  throw std::invalid_argument("make_device_adapter: unknown device kind " +
                              std::to_string(static_cast<int>(kind)));
}

}  // namespace navaid::interaction
