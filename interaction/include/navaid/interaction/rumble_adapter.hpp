#pragma once
// The BYU augmented cane's two Wii remotes (seed augmented-cane-point-cloud-obstacle-avoidance,
// thesis §2, Table 2.1): index 0 the left remote, 1 the right. Rumble is binary; the planner has
// already chosen the Table 2.1 state (cue.rumble):
//   off   both off      forward cost below the forward threshold
//   left  left on       forward cost above it and C_L < C_R (the left side is open)
//   right right on      forward cost above it and C_R < C_L
//   both  both on       forward cost above it and both side costs above the left-right threshold
// The thesis toggles the rumble once per laser scan; we refresh at 10 Hz (refresh_hz) and hold
// each command a little longer, so a continuous state has no gap and a lost link stops within
// about 0.1 s. Ours: stop is both on (the thesis' "stop and locate an open path"), as is an
// obstacle cue that carries no rumble state; every other cue has no rumble pattern.
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction {

struct RumbleConfig {
  double refresh_hz = 10.0;
  double hold_margin = 0.25;  ///< hold = period x (1 + margin)
};

/// Keys interaction.rumble.refresh_hz in [1, 100], .hold_margin in [0.01, 1].
RumbleConfig read_rumble_config(const Config& config);

class RumbleAdapter final : public DeviceAdapter {
 public:
  static constexpr int kLeft = 0, kRight = 1;
  static constexpr int kCount = 2;
  /// The Wii remote's rumble is on or off: always full scale.
  static constexpr int kOnLevel = 1000;

  /// Throws std::invalid_argument on a config read_rumble_config would reject.
  explicit RumbleAdapter(const RumbleConfig& config = {});

  DeviceKind kind() const override { return DeviceKind::kRumble; }
  std::optional<ActuatorPattern> pattern(const Cue& cue) const override;
  double refresh_period_s() const override { return 1.0 / config_.refresh_hz; }
  int actuator_count() const override { return kCount; }
  std::string_view actuator_name(int index) const override;
  const RumbleConfig& config() const { return config_; }

 private:
  RumbleConfig config_;
  std::uint16_t hold_ms_;
};

}  // namespace navaid::interaction
