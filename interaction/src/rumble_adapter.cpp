#include "navaid/interaction/rumble_adapter.hpp"

#include "navaid/interaction/config_schema.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "adapter_support.hpp"

namespace navaid::interaction {

namespace {

constexpr std::array<std::string_view, RumbleAdapter::kCount> kRumbleAdapterNames{"left", "right"};

}  // namespace

namespace {
const ConfigKey<double> kRumbleAdapterRefresh{"interaction.rumble.refresh_hz", RumbleConfig{}.refresh_hz, {1.0, 100.0},
                                 "the rumble remotes' refresh rate [Hz]"};
const ConfigKey<double> kRumbleAdapterHoldMargin{"interaction.rumble.hold_margin", RumbleConfig{}.hold_margin, {0.01, 1.0},
                                    "a rumble is held for the refresh period times (1 + this)"};
}  // namespace

ConfigSchema rumble_config_schema() { return ConfigSchema().add(kRumbleAdapterRefresh).add(kRumbleAdapterHoldMargin); }

RumbleConfig read_rumble_config(const Config& config) {
  RumbleConfig c;
  c.refresh_hz = get(config, kRumbleAdapterRefresh);
  c.hold_margin = get(config, kRumbleAdapterHoldMargin);
  return c;
}

RumbleAdapter::RumbleAdapter(const RumbleConfig& config) : config_(config) {
  detail::require(config_.refresh_hz >= 1.0 && config_.refresh_hz <= 100.0, "rumble: refresh_hz must be in [1, 100]");
  detail::require(config_.hold_margin >= 0.01 && config_.hold_margin <= 1.0, "rumble: hold_margin must be in [0.01, 1]");
  hold_ms_ = refresh_hold_ms(1.0 / config_.refresh_hz, config_.hold_margin);
}

std::string_view RumbleAdapter::actuator_name(int index) const {
  if (index < 0 || index >= kCount) throw std::out_of_range("rumble: no actuator " + std::to_string(index));
  return kRumbleAdapterNames[static_cast<std::size_t>(index)];
}

std::optional<ActuatorPattern> RumbleAdapter::pattern(const Cue& cue) const {
  ActuatorPattern p = detail::empty_pattern(cue.t, DeviceKind::kRumble);
  bool left = false;
  bool right = false;
  switch (cue.kind) {
    case CueKind::kObstacle:
      // Table 2.1; without a state (another planner's obstacle): both, as for stop (ours).
      switch (cue.rumble.value_or(planning::RumbleState::kBoth)) {
        case planning::RumbleState::kOff: break;
        case planning::RumbleState::kLeft: left = true; break;
        case planning::RumbleState::kRight: right = true; break;
        case planning::RumbleState::kBoth: left = right = true; break;
      }
      break;
    case CueKind::kStop:
      left = right = true;
      break;
    case CueKind::kArrive:
    case CueKind::kTurn:
    case CueKind::kVeer:
    case CueKind::kOnCourse:
    case CueKind::kObjectDirection:
    case CueKind::kSystem:
      return std::nullopt;
  }
  if (left) p.commands.push_back(detail::command(kLeft, kOnLevel, 0, 0, hold_ms_));
  if (right) p.commands.push_back(detail::command(kRight, kOnLevel, 0, 0, hold_ms_));
  return p;
}

}  // namespace navaid::interaction
