// GuidanceCommand's names: to_string and *_from_string of action, reason, rumble state and hand
// direction come from one table per enum (the guidance timeline CSV writes and reads them).
#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <vector>

#include "navaid/planning/guidance_command.hpp"

namespace navaid::planning {
namespace {

// Every enumerator with its name; a dropped or misspelt table entry fails.

TEST(GuidanceCommandNames, EveryActionRoundTrips) {
  const std::vector<std::pair<GuidanceAction, std::string_view>> actions{
      {GuidanceAction::kGo, "go"},
      {GuidanceAction::kStop, "stop"},
      {GuidanceAction::kWait, "wait"},
      {GuidanceAction::kArrived, "arrived"},
  };
  for (const auto& [action, name] : actions) {
    EXPECT_EQ(to_string(action), name);
    EXPECT_EQ(guidance_action_from_string(to_string(action)), action) << name;
  }
}

TEST(GuidanceCommandNames, EveryReasonRoundTrips) {
  const std::vector<std::pair<GuidanceReason, std::string_view>> reasons{
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
  };
  for (const auto& [reason, name] : reasons) {
    EXPECT_EQ(to_string(reason), name);
    EXPECT_EQ(guidance_reason_from_string(to_string(reason)), reason) << name;
  }
}

TEST(GuidanceCommandNames, EveryRumbleStateRoundTrips) {
  const std::vector<std::pair<RumbleState, std::string_view>> states{
      {RumbleState::kOff, "off"},
      {RumbleState::kLeft, "left"},
      {RumbleState::kRight, "right"},
      {RumbleState::kBoth, "both"},
  };
  for (const auto& [state, name] : states) {
    EXPECT_EQ(to_string(state), name);
    EXPECT_EQ(rumble_state_from_string(to_string(state)), state) << name;
  }
}

TEST(GuidanceCommandNames, EveryHandDirectionRoundTrips) {
  const std::vector<std::pair<HandDirection, std::string_view>> directions{
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
  };
  for (const auto& [direction, name] : directions) {
    EXPECT_EQ(to_string(direction), name);
    EXPECT_EQ(hand_direction_from_string(to_string(direction)), direction) << name;
  }
}

TEST(GuidanceCommandNames, UnknownNamesAndValues) {
  EXPECT_EQ(guidance_action_from_string("Go"), std::nullopt);
  EXPECT_EQ(guidance_reason_from_string("path_found"), std::nullopt);
  EXPECT_EQ(rumble_state_from_string(""), std::nullopt);
  EXPECT_EQ(hand_direction_from_string("upright"), std::nullopt);
  EXPECT_EQ(hand_direction_from_string("unknown"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<GuidanceAction>(40)), "unknown");
  EXPECT_EQ(to_string(static_cast<GuidanceReason>(40)), "unknown");
  EXPECT_EQ(to_string(static_cast<RumbleState>(40)), "unknown");
  EXPECT_EQ(to_string(static_cast<HandDirection>(40)), "unknown");
}

}  // namespace
}  // namespace navaid::planning
