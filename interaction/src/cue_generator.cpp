#include "navaid/interaction/cue_generator.hpp"

#include <fmt/format.h>

#include <cmath>

#include "navaid/core/enum_names.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/interaction/config_schema.hpp"
#include "navaid/planning/angles.hpp"

namespace navaid::interaction {

using planning::deg_to_rad;
using planning::GuidanceAction;
using planning::GuidanceReason;

namespace {

constexpr NameTable<CueModality, 3> kModalityNames{{
    {CueModality::kBoth, "both"},
    {CueModality::kHaptic, "haptic"},
    {CueModality::kAudio, "audio"},
}};

}  // namespace

namespace {
const CueGeneratorConfig kCueGeneratorDefaults;
const ConfigKey<double> kOnCourse{"interaction.cues.on_course_deg", 10.0, {1.0, 45.0},
                                  "heading errors below this are on course [deg]"};
const ConfigKey<double> kTurn{"interaction.cues.turn_deg", 30.0, {1.0, 90.0},
                              "heading errors above this are turns, between the two veers [deg] (> on_course_deg)"};
const ConfigKey<double> kHysteresis{"interaction.cues.hysteresis_deg", 3.0, {0.0, 10.0},
                                    "margin a heading must cross to change class [deg]"};
const ConfigKey<double> kMinConfidence{"interaction.cues.min_confidence", kCueGeneratorDefaults.min_confidence, {0.0, 1.0},
                                       "below this guidance confidence the user is told to wait (locating)"};
const ConfigKey<double> kLocatingRepeat{"interaction.cues.locating_repeat_s", kCueGeneratorDefaults.locating_repeat_s, {1.0, 120.0},
                                        "while locating, the message is repeated this often [s]"};
const ConfigKey<double> kTtlHaptic{"interaction.cues.ttl_haptic_s", kCueGeneratorDefaults.ttl_haptic_s, {0.1, 60.0},
                                   "a direction cue older than this is stale [s]"};
const ConfigKey<double> kTtlSpeech{"interaction.cues.ttl_speech_s", kCueGeneratorDefaults.ttl_speech_s, {0.1, 60.0},
                                   "a spoken cue not started within this is dropped [s]"};
const ConfigKey<double> kTtlSystem{"interaction.cues.ttl_system_s", kCueGeneratorDefaults.ttl_system_s, {0.1, 60.0},
                                   "a system message not started within this is dropped [s]"};
const ConfigKey<std::string> kModality{"interaction.cues.modality", std::string("both"), enum_names(kModalityNames),
                                        "cue channels: both, haptic only or audio only"};

}  // namespace

CueGeneratorConfig read_cue_generator_config(const Config& config) {
  CueGeneratorConfig c;
  const double on_course = get(config, kOnCourse);
  const double turn = get(config, kTurn);
  const double hysteresis = get(config, kHysteresis);
  if (!(turn > on_course)) {
    throw ConfigError("", "interaction.cues.turn_deg", fmt::format("interaction.cues.turn_deg ({}) must exceed interaction.cues.on_course_deg ({})",
                                  turn, on_course));
  }
  // A margin as wide as the gap between the thresholds would let a heading skip the veer class.
  if (!(2.0 * hysteresis < turn - on_course) || !(hysteresis < on_course)) {
    throw ConfigError("", "interaction.cues.hysteresis_deg", fmt::format("interaction.cues.hysteresis_deg ({}) must be below half the gap between "
                                  "on_course_deg ({}) and turn_deg ({}) and below on_course_deg",
                                  hysteresis, on_course, turn));
  }
  c.on_course_rad = deg_to_rad(on_course);
  c.turn_rad = deg_to_rad(turn);
  c.hysteresis_rad = deg_to_rad(hysteresis);
  c.min_confidence = get(config, kMinConfidence);
  c.locating_repeat_s = get(config, kLocatingRepeat);
  c.ttl_haptic_s = get(config, kTtlHaptic);
  c.ttl_speech_s = get(config, kTtlSpeech);
  c.ttl_system_s = get(config, kTtlSystem);
  c.modality = *cue_modality_from_string(get(config, kModality));
  return c;
}

ConfigSchema cue_generator_config_schema() {
  return ConfigSchema()
      .add(kOnCourse)
      .add(kTurn)
      .add(kHysteresis)
      .add(kMinConfidence)
      .add(kLocatingRepeat)
      .add(kTtlHaptic)
      .add(kTtlSpeech)
      .add(kTtlSystem)
      .add(kModality);
}

ConfigSchema config_schema() {
  return ConfigSchema()
      .add(cue_generator_config_schema())
      .add(cue_policy_config_schema())
      .add(belt_config_schema())
      .add(hand_unit_config_schema())
      .add(rumble_config_schema())
      .add(steering_wheel_config_schema())
      .add(speech_config_schema())
      .add(link_config_schema())
      .add(route_timeline_config_schema());
}

std::string_view to_string(CueModality modality) { return enum_name(kModalityNames, modality); }

std::optional<CueModality> cue_modality_from_string(std::string_view name) {
  return enum_value(kModalityNames, name);
}

CueGenerator::CueGenerator(CueGeneratorConfig config) : config_(config) {}

HeadingClass CueGenerator::classify(double heading_rad, std::optional<HeadingClass> previous) const {
  const double a = std::abs(heading_rad);
  const double h = config_.hysteresis_rad;
  // The thresholds move away from the previous class by h: staying is easier than leaving.
  const double on_course = previous == HeadingClass::kOnCourse ? config_.on_course_rad + h
                                                               : config_.on_course_rad - (previous ? h : 0.0);
  const double turn = previous == HeadingClass::kTurn ? config_.turn_rad - h
                                                      : config_.turn_rad + (previous ? h : 0.0);
  if (a <= on_course) return HeadingClass::kOnCourse;
  if (a <= turn) return HeadingClass::kVeer;
  return HeadingClass::kTurn;
}

Cue CueGenerator::make(Timestamp t, CueKind kind) const {
  Cue cue;
  cue.t = t;
  cue.kind = kind;
  cue.priority = default_priority(kind);
  cue.intensity = config_.intensity;
  cue.ttl_s = config_.ttl_haptic_s;
  return cue;
}

Cue CueGenerator::spoken(Timestamp t, CueKind kind, MessageCategory category, std::string id,
                         std::map<std::string, std::string> args) const {
  Cue cue = make(t, kind);
  cue.ttl_s = category == MessageCategory::kSystem ? config_.ttl_system_s : config_.ttl_speech_s;
  cue.message = SpokenMessage{category, std::move(id), std::move(args)};
  return cue;
}

std::vector<Cue> CueGenerator::locating(Timestamp t) {
  heading_class_.reset();
  const bool due = !locating_since_said_ ||
                   ns_to_seconds(t - *locating_since_said_) >= config_.locating_repeat_s;
  locating_ = true;
  if (!due) return {};
  locating_since_said_ = t;
  return {spoken(t, CueKind::kSystem, MessageCategory::kSystem, "locating")};
}

std::vector<Cue> CueGenerator::on_guidance(const planning::GuidanceCommand& command) {
  return for_modality(guidance_cues(command));
}

std::vector<Cue> CueGenerator::for_modality(std::vector<Cue> cues) const {
  for (Cue& cue : cues) {
    switch (config_.modality) {
      case CueModality::kBoth: break;
      case CueModality::kHaptic:
        if (cue.message && cue.message->category == MessageCategory::kAction && cue.kind != CueKind::kStop) {
          cue.message.reset();
        }
        break;
      case CueModality::kAudio:
        cue.felt = false;
        if (cue.message) break;
        if (cue.kind == CueKind::kVeer && cue.direction_rad) {
          cue.message = SpokenMessage{MessageCategory::kAction, "bear", {{"side", *cue.direction_rad > 0.0 ? "left" : "right"}}};
        } else if (cue.kind == CueKind::kObstacle) {
          const planning::RumbleState r = cue.rumble.value_or(planning::RumbleState::kBoth);
          const char* way = r == planning::RumbleState::kLeft ? "left" : r == planning::RumbleState::kRight ? "right" : "stop";
          cue.message = SpokenMessage{MessageCategory::kAction, "obstacle", {{"way", way}}};
        }
        if (cue.message) cue.ttl_s = config_.ttl_speech_s;  // now a spoken cue: it may wait as long
        break;
    }
  }
  return cues;
}

std::vector<Cue> CueGenerator::guidance_cues(const planning::GuidanceCommand& command) {
  if (guidance_stopped_) return {};
  const Timestamp t = command.t;
  const bool unsure_go = command.action == GuidanceAction::kGo && command.confidence < config_.min_confidence;
  const bool wait_locating = command.action == GuidanceAction::kWait &&
                             (command.reason == GuidanceReason::kLocating ||
                              command.reason == GuidanceReason::kRegistrationUncertain);
  if (wait_locating || unsure_go) return locating(t);

  std::vector<Cue> cues;
  if (locating_) {
    locating_ = false;
    locating_since_said_.reset();
    cues.push_back(spoken(t, CueKind::kSystem, MessageCategory::kSystem, "located"));
  }
  const auto remember = [&](Cue cue) {
    if (cue.message) last_guidance_message_ = cue.message;
    cues.push_back(std::move(cue));
  };
  switch (command.action) {
    case GuidanceAction::kWait:
      // Waiting for another reason (e.g. the target was never seen): nothing to steer by.
      heading_class_.reset();
      break;
    case GuidanceAction::kStop: {
      heading_class_.reset();
      Cue cue = spoken(t, CueKind::kStop, MessageCategory::kAction, "stop");
      cue.rumble = command.rumble;
      remember(std::move(cue));
      break;
    }
    case GuidanceAction::kArrived: {
      heading_class_.reset();
      const bool target = command.reason == GuidanceReason::kTargetReached;
      if (!target && command.heading_rad) {
        // Where the destination's landmark lies, as a clock position (the user turns to face it).
        Cue cue = make(t, CueKind::kArrive);
        cue.direction_rad = command.heading_rad;
        cue.message = SpokenMessage{MessageCategory::kRoute, "arrived_facing",
                                    {{"clock", std::to_string(clock_position(*command.heading_rad))}}};
        remember(std::move(cue));
        break;
      }
      remember(spoken(t, CueKind::kArrive, target ? MessageCategory::kAction : MessageCategory::kRoute,
                      target ? "target_reached" : "arrived"));
      break;
    }
    case GuidanceAction::kGo: {
      if (command.hand) {
        Cue cue = make(t, CueKind::kObjectDirection);
        cue.hand = command.hand;
        if (*command.hand != planning::HandDirection::kHold) {
          cue.message = SpokenMessage{MessageCategory::kAction, "move_hand",
                                      {{"direction", std::string(planning::to_string(*command.hand))}}};
        }
        remember(std::move(cue));
      } else if (command.rumble) {
        const bool open = *command.rumble == planning::RumbleState::kOff;
        Cue cue = make(t, open ? CueKind::kOnCourse : CueKind::kObstacle);
        cue.rumble = command.rumble;
        cues.push_back(std::move(cue));
      } else if (command.heading_rad) {
        const HeadingClass cls = classify(*command.heading_rad, heading_class_);
        const bool entering_turn = cls == HeadingClass::kTurn && heading_class_ != HeadingClass::kTurn;
        heading_class_ = cls;
        Cue cue = make(t, cls == HeadingClass::kTurn   ? CueKind::kTurn
                          : cls == HeadingClass::kVeer ? CueKind::kVeer
                                                       : CueKind::kOnCourse);
        cue.direction_rad = command.heading_rad;
        cue.steering_rad = command.steering_rad;
        if (entering_turn) {
          cue.message = SpokenMessage{MessageCategory::kAction, "prepare_turn",
                                      {{"side", *command.heading_rad > 0.0 ? "left" : "right"}}};
          last_guidance_message_ = cue.message;
        }
        cues.push_back(std::move(cue));
      }
      break;
    }
  }
  return cues;
}

std::vector<Cue> CueGenerator::on_event(const SystemEvent& event) {
  const Timestamp t = event.t;
  const auto system = [&](std::string id, std::map<std::string, std::string> args = {}) {
    return std::vector<Cue>{spoken(t, CueKind::kSystem, MessageCategory::kSystem, std::move(id), std::move(args))};
  };
  // A state announced once per change, never on every frame.
  const auto on_change = [&](bool& up, bool now_up, const char* lost, const char* restored) -> std::vector<Cue> {
    if (up == now_up) return {};
    up = now_up;
    return system(now_up ? restored : lost);
  };
  switch (event.kind) {
    case SystemEventKind::kInitialized:
      if (initialized_said_) return {};
      initialized_said_ = true;
      return system("initialized");
    case SystemEventKind::kEstimatorMode: {
      const bool changed = mode_ && *mode_ != event.value;
      mode_ = event.value;
      if (!changed) return {};
      return system("mode_changed", {{"mode", event.value}});
    }
    case SystemEventKind::kNetworkLost: return on_change(network_up_, false, "network_lost", "network_restored");
    case SystemEventKind::kNetworkRestored: return on_change(network_up_, true, "network_lost", "network_restored");
    case SystemEventKind::kLinkLost: return on_change(link_up_, false, "link_lost", "link_restored");
    case SystemEventKind::kLinkRestored: return on_change(link_up_, true, "link_lost", "link_restored");
    case SystemEventKind::kCameraFault: return system("camera_fault", {{"what", event.value}});
    case SystemEventKind::kRouteInstruction: {
      // "<distance_m>;<left|right|straight|cross|steps>[;<road>]"
      const std::size_t a = event.value.find(';');
      if (a == std::string::npos) {
        throw Error(fmt::format("route instruction '{}': expected <distance_m>;<left|right|straight|cross|steps>[;<road>]",
                                event.value));
      }
      const std::size_t b = event.value.find(';', a + 1);
      const std::string what = event.value.substr(a + 1, b == std::string::npos ? b : b - a - 1);
      std::map<std::string, std::string> args{{"distance_m", event.value.substr(0, a)}};
      if (b != std::string::npos && b + 1 < event.value.size()) args["road"] = event.value.substr(b + 1);
      std::string id = "route";
      if (what == "cross") {
        id = "route_crossing";
      } else if (what == "steps") {
        id = "route_steps";
        args.erase("road");
      } else {
        args["turn"] = what;
      }
      Cue cue = spoken(t, CueKind::kSystem, MessageCategory::kRoute, std::move(id), std::move(args));
      cue.priority = default_priority(CueKind::kTurn);
      last_guidance_message_ = cue.message;
      last_route_message_ = cue.message;
      return {cue};
    }
    case SystemEventKind::kVoiceCommand: {
      const std::string& v = event.value;
      if (v == "repeat" || v == "where am i") {
        const std::optional<SpokenMessage>& again = v == "repeat" ? last_guidance_message_ : last_route_message_;
        if (!again) return system(locating_ ? "locating" : "no_instruction");
        Cue cue = spoken(t, CueKind::kSystem, again->category, again->id, again->args);
        cue.repeat = true;
        return {cue};
      }
      if (v == "stop guidance") {
        guidance_stopped_ = true;
        heading_class_.reset();
        std::vector<Cue> cues = system("guidance_stopped");
        cues.front().clear_haptics = true;
        return cues;
      }
      if (v.rfind("go to ", 0) == 0 && v.size() > 6) {
        guidance_stopped_ = false;
        Cue cue = spoken(t, CueKind::kSystem, MessageCategory::kRoute, "destination_set", {{"place", v.substr(6)}});
        return {cue};
      }
      return system("not_understood");
    }
  }
  return {};
}

}  // namespace navaid::interaction
