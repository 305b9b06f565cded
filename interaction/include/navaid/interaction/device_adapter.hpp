#pragma once
// A device adapter maps one Cue to the ActuatorPattern that expresses it on one device, with the
// rules of that device's seed paper (docs/interaction-devices.md has the tables). Adapters are
// stateless: the same cue always gives the same pattern, so the scheduler may re-send it every
// refresh_period_s() and a replay is bit for bit.
//
// Holds: every command carries a hold time after which the controller switches the actuator off
// by itself. For a cue the scheduler keeps refreshing, hold = refresh period x (1 + hold_margin),
// a little longer than the period (no gap between refreshes) and short enough that a lost link
// stops the motor within about one period. One-shot patterns (belt and hand arrival, the hand
// unit's one-second command) are held exactly as long as they should last.
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/core/time.hpp"
#include "navaid/interaction/actuator_pattern.hpp"
#include "navaid/interaction/cue.hpp"

namespace navaid::interaction {

class DeviceAdapter {
 public:
  virtual ~DeviceAdapter() = default;
  virtual DeviceKind kind() const = 0;
  /// The pattern expressing `cue` on this device at time cue.t, or nullopt when the device
  /// cannot express it (speech carries it then). An empty `commands` list = all actuators off.
  virtual std::optional<ActuatorPattern> pattern(const Cue& cue) const = 0;
  /// The pattern that switches everything off (sent on stop of guidance and shutdown).
  ActuatorPattern all_off(Timestamp t) const;
  /// How often the scheduler re-sends the current haptic cue [s].
  virtual double refresh_period_s() const = 0;
  virtual int actuator_count() const = 0;
  /// Throws std::out_of_range outside [0, actuator_count()).
  virtual std::string_view actuator_name(int index) const = 0;
};

/// The hold of a refreshed command: period_s x (1 + margin) in whole milliseconds, rounded up.
/// Throws std::invalid_argument when period_s or margin is not positive or the hold exceeds
/// 65535 ms (the link's field).
std::uint16_t refresh_hold_ms(double period_s, double margin);

/// Reads interaction.<device>.* keys (range-checked; ConfigError when out of range).
std::unique_ptr<DeviceAdapter> make_device_adapter(DeviceKind kind, const Config& config);

}  // namespace navaid::interaction
