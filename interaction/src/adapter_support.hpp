#pragma once
// Small helpers the device adapters share. Private to the interaction room.
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/cue.hpp"

namespace navaid::interaction::detail {

/// Constructor checks: the read_*_config functions give ConfigErrors naming the key; a config
/// built in code gets this.
inline void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

inline ActuatorCommand command(int actuator, int level, int on_ms, int off_ms, int hold_ms) {
  ActuatorCommand c;
  c.actuator = static_cast<std::uint8_t>(actuator);
  c.level = static_cast<std::int16_t>(level);
  c.on_ms = static_cast<std::uint16_t>(on_ms);
  c.off_ms = static_cast<std::uint16_t>(off_ms);
  c.hold_ms = static_cast<std::uint16_t>(hold_ms);
  return c;
}

inline ActuatorPattern empty_pattern(Timestamp t, DeviceKind device) {
  ActuatorPattern p;
  p.t = t;
  p.device = device;
  return p;
}

/// +1 for a direction to the left, -1 to the right; nullopt when there is no side to show
/// (absent, zero or not finite: a turn or veer cue like that is the generator's bug, and a
/// wrong side is worse than none).
inline std::optional<int> side_of(const std::optional<double>& direction_rad) {
  if (!direction_rad || !std::isfinite(*direction_rad) || *direction_rad == 0.0) return std::nullopt;
  return *direction_rad > 0.0 ? 1 : -1;
}

}  // namespace navaid::interaction::detail
