#include "navaid/planning/guidance_command.hpp"

#include "navaid/core/enum_names.hpp"

namespace navaid::planning {

namespace {

constexpr NameTable<GuidanceAction, 4> kActionNames{{
    {GuidanceAction::kGo, "go"},
    {GuidanceAction::kStop, "stop"},
    {GuidanceAction::kWait, "wait"},
    {GuidanceAction::kArrived, "arrived"},
}};

constexpr NameTable<GuidanceReason, 14> kReasonNames{{
    {GuidanceReason::kPathFound, "path-found"},
    {GuidanceReason::kObstacleAhead, "obstacle-ahead"},
    {GuidanceReason::kNoPath, "no-path"},
    {GuidanceReason::kSearchLimit, "search-limit"},
    {GuidanceReason::kStartBlocked, "start-blocked"},
    {GuidanceReason::kGoalBlocked, "goal-blocked"},
    {GuidanceReason::kOffMap, "off-map"},
    {GuidanceReason::kLocating, "locating"},
    {GuidanceReason::kRegistrationUncertain, "registration-uncertain"},
    {GuidanceReason::kTargetNotSeen, "target-not-seen"},
    {GuidanceReason::kTargetFar, "target-far"},
    {GuidanceReason::kTargetReached, "target-reached"},
    {GuidanceReason::kTargetInView, "target-in-view"},
    {GuidanceReason::kTargetRemembered, "target-remembered"},
}};

constexpr NameTable<RumbleState, 4> kRumbleNames{{
    {RumbleState::kOff, "off"},
    {RumbleState::kLeft, "left"},
    {RumbleState::kRight, "right"},
    {RumbleState::kBoth, "both"},
}};

constexpr NameTable<HandDirection, 11> kHandNames{{
    {HandDirection::kHold, "hold"},
    {HandDirection::kRight, "right"},
    {HandDirection::kUpRight, "up-right"},
    {HandDirection::kUp, "up"},
    {HandDirection::kUpLeft, "up-left"},
    {HandDirection::kLeft, "left"},
    {HandDirection::kDownLeft, "down-left"},
    {HandDirection::kDown, "down"},
    {HandDirection::kDownRight, "down-right"},
    {HandDirection::kForward, "forward"},
    {HandDirection::kBackward, "backward"},
}};

}  // namespace

std::string_view to_string(GuidanceAction action) { return enum_name(kActionNames, action); }
std::optional<GuidanceAction> guidance_action_from_string(std::string_view name) {
  return enum_value(kActionNames, name);
}

std::string_view to_string(GuidanceReason reason) { return enum_name(kReasonNames, reason); }
std::optional<GuidanceReason> guidance_reason_from_string(std::string_view name) {
  return enum_value(kReasonNames, name);
}

std::string_view to_string(RumbleState state) { return enum_name(kRumbleNames, state); }
std::optional<RumbleState> rumble_state_from_string(std::string_view name) { return enum_value(kRumbleNames, name); }

std::string_view to_string(HandDirection direction) { return enum_name(kHandNames, direction); }
std::optional<HandDirection> hand_direction_from_string(std::string_view name) {
  return enum_value(kHandNames, name);
}

}  // namespace navaid::planning
