#pragma once
// What the planning layer hands to interaction: one command per planning cycle. Every planner
// (Direction A* + path following, WPG + PI heading control, BYU cost functions, W-ROMA hand
// guidance) fills the common part {action, reason, confidence} and the field of its own device;
// interaction maps it to vibration and speech. A command never carries a direction when the
// estimate is too unsure to give one: then action is kStop or kWait and reason says why.
#include <optional>
#include <string>
#include <string_view>

#include "navaid/core/geometry.hpp"
#include "navaid/core/time.hpp"

namespace navaid::planning {

enum class GuidanceAction {
  kGo,       ///< walk (or move the hand) in the commanded direction
  kStop,     ///< stop now: the way ahead is blocked or unsafe
  kWait,     ///< stand still until the system knows where the user is (reason says why)
  kArrived,  ///< the goal (or the target object) is reached
};

enum class GuidanceReason {
  kPathFound,             ///< a collision-free path is being followed
  kObstacleAhead,         ///< an obstacle blocks the way ahead
  kNoPath,                ///< the search exhausted the map without reaching the goal
  kSearchLimit,           ///< the search hit its node or time limit (see SearchLimits)
  kStartBlocked,          ///< the user stands inside an obstacle (or its inflation)
  kGoalBlocked,           ///< the goal lies inside an obstacle
  kOffMap,                ///< the start or goal lies outside the map
  kLocating,              ///< the estimator is initializing, lost, or its heading sigma is too large
  kRegistrationUncertain, ///< the GPS-map registration is too unsure to follow a route
  kTargetNotSeen,         ///< hand guidance: the target object was never seen
  kTargetFar,             ///< hand guidance case II: seen beyond the depth range, walk towards it
  kTargetReached,         ///< hand guidance: the hand is at the object
  kTargetInView,          ///< hand guidance case I: detected now, centre from the depth patch
  kTargetRemembered,      ///< hand guidance case III: not in view, stored centre through the pose
};

std::string_view to_string(GuidanceAction action);
std::string_view to_string(GuidanceReason reason);
/// Inverses of to_string (one name table each); nullopt for unknown names.
std::optional<GuidanceAction> guidance_action_from_string(std::string_view name);
std::optional<GuidanceReason> guidance_reason_from_string(std::string_view name);

/// The BYU augmented cane's two rumble remotes (thesis Table 2.1).
enum class RumbleState { kOff, kLeft, kRight, kBoth };
std::string_view to_string(RumbleState state);
std::optional<RumbleState> rumble_state_from_string(std::string_view name);

/// W-ROMA's hand unit: 8 sectors of the virtual image plane (by motor or motor pair) plus the
/// forward / backward motors, or "hold" when the hand is aligned (paper §IV).
enum class HandDirection { kHold, kRight, kUpRight, kUp, kUpLeft, kLeft, kDownLeft, kDown, kDownRight, kForward, kBackward };
std::string_view to_string(HandDirection direction);
std::optional<HandDirection> hand_direction_from_string(std::string_view name);

struct GuidanceCommand {
  Timestamp t = 0;
  GuidanceAction action = GuidanceAction::kWait;
  GuidanceReason reason = GuidanceReason::kLocating;
  /// How sure the planner is that following the command is right, in [0, 1]: 1 with a sure
  /// estimate and a clear way, falling with position / heading sigma and with blocked look-ahead.
  double confidence = 0.0;

  /// Walking direction relative to the user's current heading [rad], positive to the left
  /// (counter-clockwise seen from above), in (-pi, pi]. Set with action kGo.
  std::optional<double> heading_rad;
  /// Distance to the next waypoint along the commanded heading [m] (path following's look-ahead
  /// after collision shortening).
  std::optional<double> lookahead_m;
  /// Steering command of the Smart Cane's PI heading controller (eq. 1) [rad].
  std::optional<double> steering_rad;
  /// BYU augmented cane rumble state (Table 2.1).
  std::optional<RumbleState> rumble;
  /// W-ROMA hand direction and the target's centre in the hand frame H [m].
  std::optional<HandDirection> hand;
  std::optional<Vec3> target_H;

  /// Human-readable detail for logs and the report (e.g. "heading sigma 21 deg > 15 deg").
  std::string detail;
};

}  // namespace navaid::planning
