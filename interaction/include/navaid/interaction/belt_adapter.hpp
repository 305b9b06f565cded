#pragma once
// eLabrador's haptic belt (seed elabrador-wearable-outdoor-navigation, §IV.C): five vibrators at
// -90 (left), -45 (front-left), 0 (front), 45 (front-right), 90 (right) deg, where the paper's
// negative angles are LEFT. Indices run from left to right: 0 left, 1 front-left, 2 front,
// 3 front-right, 4 right.
//
// The paper's rules (the cue generator has already applied its 30 / 10 deg thresholds):
//   turn  (> 30 deg off)  the -90 / +90 vibrator continuously, on the side of the direction
//   veer  (10..30 deg)    the -45 / +45 vibrator continuously
//   on course (<= 10 deg) the 0 vibrator intermittently
// at 1 Hz, binary on/off, with a low and a high intensity mode the user chooses.
// Ours (the paper does not say): stop pulses all five fast at the high level; an obstacle pulses
// the +-45 vibrator of the open side fast at the high level (no open side, or both: like stop);
// arrival pulses the front three twice; object direction and system cues have no belt pattern.
#include <array>
#include <optional>
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction {

struct BeltConfig {
  double refresh_hz = 1.0;     ///< the paper's 1 Hz
  double hold_margin = 0.25;   ///< hold = period x (1 + margin)
  int level_low = 400;         ///< per mille, the low intensity mode
  int level_high = 1000;       ///< per mille, the high intensity mode
  /// The user's intensity mode; unset: each cue's own intensity.
  std::optional<CueIntensity> intensity;
  int pulse_on_ms = 200;       ///< on-course: the front vibrator's on time
  int pulse_off_ms = 300;      ///< on-course: its off time (two pulses per second)
  int urgent_on_ms = 100;      ///< stop and obstacle: the fast pulse
  int urgent_off_ms = 100;
  int arrive_on_ms = 200;      ///< arrival: two pulses of this length ...
  int arrive_off_ms = 200;     ///< ... with this pause between them
};

/// Keys interaction.belt.refresh_hz in [0.1, 20], .hold_margin in [0.01, 1], .level_low and
/// .level_high in [1, 1000] with level_low <= level_high, .intensity low|high (absent: the cue's),
/// .pulse_on_ms / .pulse_off_ms / .urgent_on_ms / .urgent_off_ms / .arrive_on_ms / .arrive_off_ms
/// in [10, 5000].
BeltConfig read_belt_config(const Config& config);

class BeltAdapter final : public DeviceAdapter {
 public:
  static constexpr int kLeft = 0, kFrontLeft = 1, kFront = 2, kFrontRight = 3, kRight = 4;
  static constexpr int kCount = 5;

  /// Throws std::invalid_argument on a config read_belt_config would reject.
  explicit BeltAdapter(const BeltConfig& config = {});

  DeviceKind kind() const override { return DeviceKind::kBelt; }
  std::optional<ActuatorPattern> pattern(const Cue& cue) const override;
  double refresh_period_s() const override { return 1.0 / config_.refresh_hz; }
  int actuator_count() const override { return kCount; }
  std::string_view actuator_name(int index) const override;
  /// The level a cue of this intensity gets (after the user's preference).
  int level_for(CueIntensity cue_intensity) const;
  const BeltConfig& config() const { return config_; }

 private:
  BeltConfig config_;
  std::uint16_t hold_ms_;
};

}  // namespace navaid::interaction
