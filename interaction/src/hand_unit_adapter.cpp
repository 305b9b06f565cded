#include "navaid/interaction/hand_unit_adapter.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "adapter_support.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"

namespace navaid::interaction {

namespace {

using planning::HandDirection;
using A = HandUnitAdapter;

constexpr std::array<std::string_view, A::kCount> kHandUnitAdapterNames{"up", "down", "left", "right", "forward", "backward"};

/// The motors of a direction: one, or the pair for a diagonal (paper §III); none for hold.
std::vector<int> motors_of(HandDirection d) {
  switch (d) {
    case HandDirection::kHold: return {};
    case HandDirection::kUp: return {A::kUp};
    case HandDirection::kDown: return {A::kDown};
    case HandDirection::kLeft: return {A::kLeft};
    case HandDirection::kRight: return {A::kRight};
    case HandDirection::kForward: return {A::kForward};
    case HandDirection::kBackward: return {A::kBackward};
    case HandDirection::kUpRight: return {A::kUp, A::kRight};
    case HandDirection::kUpLeft: return {A::kUp, A::kLeft};
    case HandDirection::kDownRight: return {A::kDown, A::kRight};
    case HandDirection::kDownLeft: return {A::kDown, A::kLeft};
  }
  return {};
}

int ms_of(double seconds) { return static_cast<int>(std::lround(seconds * 1000.0)); }

void check(const HandUnitConfig& c) {
  detail::require(c.period_s >= 0.2 && c.period_s <= 10.0, "hand: period_s must be in [0.2, 10]");
  detail::require(c.hold_s >= 0.05 && c.hold_s <= 10.0 && c.hold_s <= c.period_s,
                  "hand: hold_s must be in [0.05, 10] and at most period_s");
  detail::require(c.level >= 1 && c.level <= 1000, "hand: level must be in [1, 1000]");
  detail::require(c.arrive_pulse_ms >= 10 && c.arrive_pulse_ms <= 5000, "hand: arrive_pulse_ms must be in [10, 5000]");
}

}  // namespace

namespace {
const HandUnitConfig kHandUnitAdapterDefaults;
const ConfigKey<double> kPeriod{"interaction.hand.period_s", kHandUnitAdapterDefaults.period_s, {0.2, 10.0},
                                "the hand unit takes a command this often [s] (W-ROMA: 2)"};
const ConfigKey<double> kHold{"interaction.hand.hold_s", kHandUnitAdapterDefaults.hold_s, {0.05, 10.0},
                              "each hand-unit pattern is held this long [s] (<= period_s)"};
const ConfigKey<int> kLevel{"interaction.hand.level", kHandUnitAdapterDefaults.level, 1, 1000, "hand-unit motor level [per mille]"};
const ConfigKey<int> kArrivePulse{"interaction.hand.arrive_pulse_ms", kHandUnitAdapterDefaults.arrive_pulse_ms, 10, 5000,
                                  "on arrival all six motors pulse this long [ms]"};
}  // namespace

ConfigSchema hand_unit_config_schema() { return ConfigSchema().add(kPeriod).add(kHold).add(kLevel).add(kArrivePulse); }

HandUnitConfig read_hand_unit_config(const Config& config) {
  HandUnitConfig c;
  c.period_s = get(config, kPeriod);
  c.hold_s = get(config, kHold);
  if (c.hold_s > c.period_s) {
    const char* key = config.has("interaction.hand.hold_s") ? "interaction.hand.hold_s" : "interaction.hand.period_s";
    throw ConfigError(config.origin(key), key,
                      "hold_s " + std::to_string(c.hold_s) + " exceeds period_s " + std::to_string(c.period_s) +
                          " (each command must end before the next, as in W-ROMA)");
  }
  c.level = get(config, kLevel);
  c.arrive_pulse_ms = get(config, kArrivePulse);
  return c;
}

HandUnitAdapter::HandUnitAdapter(const HandUnitConfig& config) : config_(config) { check(config_); }

std::string_view HandUnitAdapter::actuator_name(int index) const {
  if (index < 0 || index >= kCount) throw std::out_of_range("hand: no actuator " + std::to_string(index));
  return kHandUnitAdapterNames[static_cast<std::size_t>(index)];
}

std::optional<ActuatorPattern> HandUnitAdapter::pattern(const Cue& cue) const {
  ActuatorPattern p = detail::empty_pattern(cue.t, DeviceKind::kHand);
  switch (cue.kind) {
    case CueKind::kObjectDirection:
      if (!cue.hand) return std::nullopt;
      // Paper: the motor (or pair) on continuously, retained for one second; kHold: all off.
      for (const int m : motors_of(*cue.hand)) {
        p.commands.push_back(detail::command(m, config_.level, 0, 0, ms_of(config_.hold_s)));
      }
      return p;
    case CueKind::kStop:
      return p;  // ours: all off, the hand freezes
    case CueKind::kArrive:
      // Ours: all six one short pulse (a one-shot pattern).
      for (int m = 0; m < kCount; ++m) p.commands.push_back(detail::command(m, config_.level, 0, 0, config_.arrive_pulse_ms));
      return p;
    case CueKind::kObstacle:
    case CueKind::kTurn:
    case CueKind::kVeer:
    case CueKind::kOnCourse:
    case CueKind::kSystem:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace navaid::interaction
