#pragma once
// GuidanceCommands and system events in, cues out. The generator owns what needs memory of the
// past: the heading class with its hysteresis (so a heading near 10 or 30 deg does not make the
// belt flicker), entering and leaving "locating", the estimator mode announced once per change,
// network and link state, and the last route/action message for "repeat". Rate limits,
// priorities and interruption are the scheduler's (cue_scheduler.hpp).
//
// Heading classes (eLabrador §IV.C): |heading| <= on_course (10 deg) on course, <= turn (30 deg)
// veer, beyond that turn. To leave a class the heading must cross its threshold by the
// hysteresis margin (ours: 3 deg); the Augmented Cane's 10 deg dead-band is the on-course
// threshold itself.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/interaction/cue.hpp"
#include "navaid/interaction/system_event.hpp"
#include "navaid/planning/guidance_command.hpp"

namespace navaid::interaction {

/// eLabrador's user preference: guidance felt, heard, or both.
///   both:   directions felt; action, route and system messages spoken.
///   haptic: directions felt; of the action messages only "Stop!" is spoken (route and system
///           information has no haptic form and is still spoken).
///   audio:  nothing felt; directions spoken instead: "Bear left." on a veer, "Prepare to turn
///           left." on a turn, "Obstacle ahead, go left." on an obstacle; silence on course.
enum class CueModality { kBoth, kHaptic, kAudio };
std::string_view to_string(CueModality modality);
std::optional<CueModality> cue_modality_from_string(std::string_view name);

struct CueGeneratorConfig {
  double on_course_rad = 0.174532925199;  ///< 10 deg (eLabrador front vibrator; Augmented Cane dead-band)
  double turn_rad = 0.523598775598;       ///< 30 deg (eLabrador +-90 deg vibrators)
  double hysteresis_rad = 0.0523598775598;  ///< 3 deg (ours)
  /// Below this GuidanceCommand confidence a kGo carries no direction: the user is told to wait
  /// ("locating") instead of being steered on a guess.
  double min_confidence = 0.2;
  /// While locating, "locating, please wait" is repeated this often [s].
  double locating_repeat_s = 10.0;
  /// Cues are made at high intensity; the user's low / high preference is the device's
  /// (interaction.belt.intensity).
  CueIntensity intensity = CueIntensity::kHigh;
  double ttl_haptic_s = 1.0;   ///< a direction cue older than this is stale
  double ttl_speech_s = 3.0;   ///< a spoken cue not started within this is dropped
  double ttl_system_s = 10.0;  ///< system messages wait longer
  CueModality modality = CueModality::kBoth;
};

/// Keys interaction.cues.on_course_deg [1, 45], turn_deg (on_course, 90], hysteresis_deg [0, 10]
/// (must stay below both thresholds' gap), min_confidence [0, 1], locating_repeat_s [1, 120],
/// ttl_haptic_s, ttl_speech_s, ttl_system_s [0.1, 60], modality (both | haptic | audio);
/// ConfigError otherwise.
CueGeneratorConfig read_cue_generator_config(const Config& config);

enum class HeadingClass { kOnCourse, kVeer, kTurn };

class CueGenerator {
 public:
  explicit CueGenerator(CueGeneratorConfig config = {});

  /// The cues of one planning cycle (usually one; none when nothing is to be said or felt).
  std::vector<Cue> on_guidance(const planning::GuidanceCommand& command);
  /// The cues of a system event (an announcement once per change; voice commands).
  std::vector<Cue> on_event(const SystemEvent& event);

  /// The heading class after hysteresis, given the previous class.
  HeadingClass classify(double heading_rad, std::optional<HeadingClass> previous) const;

  const CueGeneratorConfig& config() const { return config_; }

 private:
  Cue make(Timestamp t, CueKind kind) const;
  Cue spoken(Timestamp t, CueKind kind, MessageCategory category, std::string id,
             std::map<std::string, std::string> args = {}) const;
  std::vector<Cue> locating(Timestamp t);
  std::vector<Cue> guidance_cues(const planning::GuidanceCommand& command);
  /// The user's modality applied to freshly made cues.
  std::vector<Cue> for_modality(std::vector<Cue> cues) const;

  CueGeneratorConfig config_;
  std::optional<HeadingClass> heading_class_;
  std::optional<Timestamp> locating_since_said_;
  bool locating_ = false;
  std::optional<std::string> mode_;
  bool network_up_ = true;
  bool link_up_ = true;
  bool initialized_said_ = false;
  bool guidance_stopped_ = false;
  std::optional<SpokenMessage> last_guidance_message_;
  std::optional<SpokenMessage> last_route_message_;
};

}  // namespace navaid::interaction
