#include "navaid/planning/guidance_command.hpp"

namespace navaid::planning {

std::string_view to_string(GuidanceAction action) {
  switch (action) {
    case GuidanceAction::kGo: return "go";
    case GuidanceAction::kStop: return "stop";
    case GuidanceAction::kWait: return "wait";
    case GuidanceAction::kArrived: return "arrived";
  }
  return "unknown";
}

std::string_view to_string(GuidanceReason reason) {
  switch (reason) {
    case GuidanceReason::kPathFound: return "path-found";
    case GuidanceReason::kObstacleAhead: return "obstacle-ahead";
    case GuidanceReason::kNoPath: return "no-path";
    case GuidanceReason::kSearchLimit: return "search-limit";
    case GuidanceReason::kStartBlocked: return "start-blocked";
    case GuidanceReason::kGoalBlocked: return "goal-blocked";
    case GuidanceReason::kOffMap: return "off-map";
    case GuidanceReason::kLocating: return "locating";
    case GuidanceReason::kRegistrationUncertain: return "registration-uncertain";
    case GuidanceReason::kTargetNotSeen: return "target-not-seen";
    case GuidanceReason::kTargetFar: return "target-far";
    case GuidanceReason::kTargetReached: return "target-reached";
    case GuidanceReason::kTargetInView: return "target-in-view";
    case GuidanceReason::kTargetRemembered: return "target-remembered";
  }
  return "unknown";
}

std::string_view to_string(RumbleState state) {
  switch (state) {
    case RumbleState::kOff: return "off";
    case RumbleState::kLeft: return "left";
    case RumbleState::kRight: return "right";
    case RumbleState::kBoth: return "both";
  }
  return "unknown";
}

std::string_view to_string(HandDirection direction) {
  switch (direction) {
    case HandDirection::kHold: return "hold";
    case HandDirection::kRight: return "right";
    case HandDirection::kUpRight: return "up-right";
    case HandDirection::kUp: return "up";
    case HandDirection::kUpLeft: return "up-left";
    case HandDirection::kLeft: return "left";
    case HandDirection::kDownLeft: return "down-left";
    case HandDirection::kDown: return "down";
    case HandDirection::kDownRight: return "down-right";
    case HandDirection::kForward: return "forward";
    case HandDirection::kBackward: return "backward";
  }
  return "unknown";
}

}  // namespace navaid::planning
