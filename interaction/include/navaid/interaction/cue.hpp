#pragma once
// The one cue schema between planning and the devices. A cue is what the user should be told,
// independent of how: the cue generator makes cues from GuidanceCommands and system events, the
// scheduler decides which reach the user and when (cue_scheduler.hpp: priorities, rate limits,
// de-duplication, interruption, time to live), device adapters turn the survivors into actuator
// patterns and the speech channel into words.
#include <cstdint>
#include <optional>
#include <string_view>

#include "navaid/core/time.hpp"
#include "navaid/interaction/spoken_message.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::interaction {

enum class CueKind {
  kStop,             ///< stop now: pre-empts everything, at once
  kObstacle,         ///< an obstacle ahead; the open side (BYU rumble) when there is one
  kArrive,           ///< the goal or the target object is reached
  kTurn,             ///< walk direction more than the turn threshold (eLabrador 30 deg) off
  kVeer,             ///< walk direction between the on-course and turn thresholds (10..30 deg) off
  kOnCourse,         ///< keep walking: within the on-course threshold (eLabrador's front vibrator)
  kObjectDirection,  ///< move the hand (W-ROMA)
  kSystem,           ///< system state: locating, mode change, link or network lost / back
};
std::string_view to_string(CueKind kind);
/// The names to_string gives ("stop", "obstacle", ...); nullopt otherwise.
std::optional<CueKind> cue_kind_from_string(std::string_view name);

enum class CueIntensity : std::uint8_t { kLow, kHigh };
std::string_view to_string(CueIntensity intensity);
std::optional<CueIntensity> cue_intensity_from_string(std::string_view name);

/// A bearing (radians, positive left, 0 ahead) as the clock position a traveller is told ("at 9
/// o'clock" = left): 1..12, 12 ahead, 30 degrees each. clock_bearing is its inverse (the middle of
/// the hour's sector).
int clock_position(double bearing_rad);
double clock_bearing(int hour);

/// Default priority of a kind: higher wins. stop 100 > obstacle 80 > arrive 60 > turn 50 >
/// object-direction 45 > veer 40 > system 30 > on-course 20.
int default_priority(CueKind kind);

struct Cue {
  Timestamp t = 0;  ///< when the cause was observed
  CueKind kind = CueKind::kSystem;
  int priority = 0;
  CueIntensity intensity = CueIntensity::kHigh;
  /// Seconds after t at which an undelivered cue is dropped as stale.
  double ttl_s = 1.0;

  /// Walking direction relative to the user's heading [rad], positive to the left (turn, veer,
  /// on-course; the GuidanceCommand's heading_rad).
  std::optional<double> direction_rad;
  /// The Smart Cane PI controller's steering output [rad], positive to the left.
  std::optional<double> steering_rad;
  /// BYU rumble state for obstacle cues (Table 2.1).
  std::optional<planning::RumbleState> rumble;
  /// W-ROMA hand direction for object-direction cues.
  std::optional<planning::HandDirection> hand;
  /// What to say with it, if anything.
  std::optional<SpokenMessage> message;
  /// Switch the device off and keep it off until the next haptic cue ("stop guidance").
  bool clear_haptics = false;
  /// Said again on request ("repeat", "where am i"): exempt from de-duplication.
  bool repeat = false;
  /// Delivered on the device; false when the user chose to hear guidance only (eLabrador's
  /// audio preference, CueModality::kAudio).
  bool felt = true;
};

}  // namespace navaid::interaction
