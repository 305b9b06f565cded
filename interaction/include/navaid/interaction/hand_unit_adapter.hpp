#pragma once
// W-ROMA's hand unit (seed w-roma-rgbd-vio-object-manipulation, §III and §V): six vibrating
// motors for up, down, left, right, forward and backward; a diagonal (up-right, up-left,
// down-right, down-left) is the PAIR of its two motors. The Bluno Nano "generates the
// corresponding vibrating pattern and retains it for one second", and the phone sends a command
// every two seconds. Indices (ours): 0 up, 1 down, 2 left, 3 right, 4 forward, 5 backward (the
// order of DeviceKind::kHand).
//
// So an object-direction cue switches its motor(s) on continuously with a hold of one second
// (hold_s), and the scheduler re-sends every two (period_s): unlike the other devices the hold is
// SHORTER than the refresh period, on purpose: the pause tells one command from the next.
// kHold (the hand is aligned) switches all off. Ours: stop switches all off (the hand should
// freeze, and a buzzing unit says "move"); arrival (target reached) gives all six one short
// pulse; walking cues (turn, veer, on course), obstacles and system cues have no pattern here.
#include <optional>
#include <string_view>

#include "navaid/core/config.hpp"
#include "navaid/interaction/device_adapter.hpp"

namespace navaid::interaction {

struct HandUnitConfig {
  double period_s = 2.0;       ///< a command every two seconds (paper)
  double hold_s = 1.0;         ///< each pattern retained for one second (paper)
  int level = 1000;            ///< per mille; the paper's motors are on/off
  int arrive_pulse_ms = 300;   ///< ours: all six this long on arrival
};

/// Keys interaction.hand.period_s in [0.2, 10], .hold_s in [0.05, 10] with hold_s <= period_s,
/// .level in [1, 1000], .arrive_pulse_ms in [10, 5000].
HandUnitConfig read_hand_unit_config(const Config& config);

class HandUnitAdapter final : public DeviceAdapter {
 public:
  static constexpr int kUp = 0, kDown = 1, kLeft = 2, kRight = 3, kForward = 4, kBackward = 5;
  static constexpr int kCount = 6;

  /// Throws std::invalid_argument on a config read_hand_unit_config would reject.
  explicit HandUnitAdapter(const HandUnitConfig& config = {});

  DeviceKind kind() const override { return DeviceKind::kHand; }
  std::optional<ActuatorPattern> pattern(const Cue& cue) const override;
  double refresh_period_s() const override { return config_.period_s; }
  int actuator_count() const override { return kCount; }
  std::string_view actuator_name(int index) const override;
  const HandUnitConfig& config() const { return config_; }

 private:
  HandUnitConfig config_;
};

}  // namespace navaid::interaction
