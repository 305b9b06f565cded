#pragma once
// What a device adapter makes of a cue and what the device link carries to the controller: per
// actuator a level and an on/off timing, each with a hold time after which the controller turns
// it off by itself, so a lost link never leaves a motor running.
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "navaid/core/time.hpp"

namespace navaid::interaction {

/// The four devices of the seeds.
enum class DeviceKind : std::uint8_t {
  kBelt = 1,    ///< eLabrador: 5 vibrators at -90 (left), -45, 0, 45, 90 (right) deg
  kHand = 2,    ///< W-ROMA: 6 motors up, down, left, right, forward, backward
  kRumble = 3,  ///< BYU augmented cane: 2 rumble remotes, left and right
  kWheel = 4,   ///< Smart Cane: the steering wheel's motor, commanded by the PI heading controller
};
std::string_view to_string(DeviceKind kind);
/// "belt", "hand", "rumble", "wheel"; nullopt otherwise.
std::optional<DeviceKind> device_kind_from_string(std::string_view name);

/// One actuator's command. Motors: level is the drive in per mille of full scale [0, 1000] (0 =
/// off). The wheel: level is the commanded steering angle in milliradians, positive to the left.
/// on_ms = 0 or off_ms = 0 means continuous while held; otherwise it pulses on_ms on, off_ms off.
struct ActuatorCommand {
  std::uint8_t actuator = 0;
  std::int16_t level = 0;
  std::uint16_t on_ms = 0;
  std::uint16_t off_ms = 0;
  std::uint16_t hold_ms = 0;  ///< the controller switches the actuator off this long after receipt
};

/// Everything one device should do from time t on; actuators not listed are switched off.
struct ActuatorPattern {
  Timestamp t = 0;
  DeviceKind device = DeviceKind::kBelt;
  std::vector<ActuatorCommand> commands;
};

}  // namespace navaid::interaction
