#include "navaid/interaction/belt_adapter.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "adapter_support.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"

namespace navaid::interaction {

namespace {

constexpr std::array<std::string_view, BeltAdapter::kCount> kBeltAdapterNames{"left", "front-left", "front", "front-right",
                                                                   "right"};

void check(const BeltConfig& c) {
  detail::require(c.refresh_hz >= 0.1 && c.refresh_hz <= 20.0, "belt: refresh_hz must be in [0.1, 20]");
  detail::require(c.hold_margin >= 0.01 && c.hold_margin <= 1.0, "belt: hold_margin must be in [0.01, 1]");
  detail::require(c.level_low >= 1 && c.level_high <= 1000 && c.level_low <= c.level_high,
                  "belt: levels must satisfy 1 <= level_low <= level_high <= 1000");
  for (const int ms : {c.pulse_on_ms, c.pulse_off_ms, c.urgent_on_ms, c.urgent_off_ms, c.arrive_on_ms,
                       c.arrive_off_ms}) {
    detail::require(ms >= 10 && ms <= 5000, "belt: pulse times must be in [10, 5000] ms");
  }
}

}  // namespace

namespace {
const BeltConfig kBeltAdapterDefaults;
const ConfigKey<double> kBeltAdapterRefresh{"interaction.belt.refresh_hz", kBeltAdapterDefaults.refresh_hz, {0.1, 20.0},
                                 "the belt's pattern refresh rate [Hz] (eLabrador: 1)"};
const ConfigKey<double> kBeltAdapterHoldMargin{"interaction.belt.hold_margin", kBeltAdapterDefaults.hold_margin, {0.01, 1.0},
                                    "a pattern is held for the refresh period times (1 + this)"};
const ConfigKey<int> kLevelLow{"interaction.belt.level_low", kBeltAdapterDefaults.level_low, 1, 1000,
                               "vibration level of the low intensity mode [per mille]"};
const ConfigKey<int> kLevelHigh{"interaction.belt.level_high", kBeltAdapterDefaults.level_high, 1, 1000,
                                "vibration level of the high intensity mode [per mille]"};
const ConfigKey<std::string> kIntensity{"interaction.belt.intensity", std::nullopt, {"low", "high"},
                                        "the user's intensity mode; absent: each cue's own intensity"};
const ConfigKey<int> kPulseOn{"interaction.belt.pulse_on_ms", kBeltAdapterDefaults.pulse_on_ms, 10, 5000,
                              "on-course: the front vibrator's on time [ms]"};
const ConfigKey<int> kPulseOff{"interaction.belt.pulse_off_ms", kBeltAdapterDefaults.pulse_off_ms, 10, 5000,
                               "on-course: the front vibrator's off time [ms]"};
const ConfigKey<int> kUrgentOn{"interaction.belt.urgent_on_ms", kBeltAdapterDefaults.urgent_on_ms, 10, 5000,
                               "stop and obstacle: the fast pulse's on time [ms]"};
const ConfigKey<int> kUrgentOff{"interaction.belt.urgent_off_ms", kBeltAdapterDefaults.urgent_off_ms, 10, 5000,
                                "stop and obstacle: the fast pulse's off time [ms]"};
const ConfigKey<int> kArriveOn{"interaction.belt.arrive_on_ms", kBeltAdapterDefaults.arrive_on_ms, 10, 5000,
                               "arrival: the length of each of two pulses [ms]"};
const ConfigKey<int> kArriveOff{"interaction.belt.arrive_off_ms", kBeltAdapterDefaults.arrive_off_ms, 10, 5000,
                                "arrival: the pause between the two pulses [ms]"};
}  // namespace

ConfigSchema belt_config_schema() {
  return ConfigSchema()
      .add(kBeltAdapterRefresh)
      .add(kBeltAdapterHoldMargin)
      .add(kLevelLow)
      .add(kLevelHigh)
      .add(kIntensity)
      .add(kPulseOn)
      .add(kPulseOff)
      .add(kUrgentOn)
      .add(kUrgentOff)
      .add(kArriveOn)
      .add(kArriveOff);
}

BeltConfig read_belt_config(const Config& config) {
  BeltConfig c;
  c.refresh_hz = get(config, kBeltAdapterRefresh);
  c.hold_margin = get(config, kBeltAdapterHoldMargin);
  c.level_low = get(config, kLevelLow);
  c.level_high = get(config, kLevelHigh);
  if (c.level_low > c.level_high) {
    const char* key = config.has("interaction.belt.level_low") ? "interaction.belt.level_low"
                                                                : "interaction.belt.level_high";
    throw ConfigError(config.origin(key), key,
                      "level_low " + std::to_string(c.level_low) + " exceeds level_high " +
                          std::to_string(c.level_high) + " (the low mode must not be the stronger)");
  }
  if (config.has(kIntensity.name)) c.intensity = cue_intensity_from_string(get(config, kIntensity));
  c.pulse_on_ms = get(config, kPulseOn);
  c.pulse_off_ms = get(config, kPulseOff);
  c.urgent_on_ms = get(config, kUrgentOn);
  c.urgent_off_ms = get(config, kUrgentOff);
  c.arrive_on_ms = get(config, kArriveOn);
  c.arrive_off_ms = get(config, kArriveOff);
  return c;
}

BeltAdapter::BeltAdapter(const BeltConfig& config) : config_(config) {
  check(config_);
  hold_ms_ = refresh_hold_ms(1.0 / config_.refresh_hz, config_.hold_margin);
}

std::string_view BeltAdapter::actuator_name(int index) const {
  if (index < 0 || index >= kCount) throw std::out_of_range("belt: no actuator " + std::to_string(index));
  return kBeltAdapterNames[static_cast<std::size_t>(index)];
}

int BeltAdapter::level_for(CueIntensity cue_intensity) const {
  const CueIntensity mode = config_.intensity.value_or(cue_intensity);
  return mode == CueIntensity::kLow ? config_.level_low : config_.level_high;
}

std::optional<ActuatorPattern> BeltAdapter::pattern(const Cue& cue) const {
  ActuatorPattern p = detail::empty_pattern(cue.t, DeviceKind::kBelt);
  const auto urgent = [&](int index) {
    return detail::command(index, config_.level_high, config_.urgent_on_ms, config_.urgent_off_ms, hold_ms_);
  };
  switch (cue.kind) {
    case CueKind::kTurn:
    case CueKind::kVeer: {
      // Paper: the +-90 (turn) or +-45 (veer) vibrator on the side to walk to, continuously.
      const auto side = detail::side_of(cue.direction_rad);
      if (!side) return std::nullopt;
      const bool turn = cue.kind == CueKind::kTurn;
      const int index = *side > 0 ? (turn ? kLeft : kFrontLeft) : (turn ? kRight : kFrontRight);
      p.commands.push_back(detail::command(index, level_for(cue.intensity), 0, 0, hold_ms_));
      return p;
    }
    case CueKind::kOnCourse:
      // Paper: the front vibrator intermittently.
      p.commands.push_back(
          detail::command(kFront, level_for(cue.intensity), config_.pulse_on_ms, config_.pulse_off_ms, hold_ms_));
      return p;
    case CueKind::kObstacle:
      // Ours: the front-side vibrator of the open side, pulsed fast; no open side: like stop.
      if (cue.rumble == planning::RumbleState::kLeft) {
        p.commands.push_back(urgent(kFrontLeft));
        return p;
      }
      if (cue.rumble == planning::RumbleState::kRight) {
        p.commands.push_back(urgent(kFrontRight));
        return p;
      }
      [[fallthrough]];
    case CueKind::kStop:
      // Ours: all five pulse fast at the high level, whatever the intensity mode: a stop must be felt.
      for (int i = 0; i < kCount; ++i) p.commands.push_back(urgent(i));
      return p;
    case CueKind::kArrive: {
      // Ours: the front three pulse twice; the hold ends the pattern after the second pulse, so
      // this is a one-shot pattern (re-sending it repeats the two pulses).
      const int hold = 2 * config_.arrive_on_ms + config_.arrive_off_ms;
      for (const int i : {kFrontLeft, kFront, kFrontRight}) {
        p.commands.push_back(
            detail::command(i, level_for(cue.intensity), config_.arrive_on_ms, config_.arrive_off_ms, hold));
      }
      return p;
    }
    case CueKind::kObjectDirection:
    case CueKind::kSystem:
      return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace navaid::interaction
