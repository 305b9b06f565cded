#include "navaid/experiments/cue_perception.hpp"

#include <cmath>
#include <cstdlib>

#include "navaid/interaction/belt_adapter.hpp"
#include "navaid/interaction/cue.hpp"
#include "navaid/interaction/rumble_adapter.hpp"

namespace navaid::experiments {

namespace {

using interaction::CueKind;
using simulation::Instruction;
using K = Instruction::Kind;

std::optional<Instruction> felt(const interaction::ActuatorPattern& p, CueKind kind, double t_s) {
  if (kind == CueKind::kStop) return Instruction{t_s, K::kStop, 0};
  if (kind == CueKind::kArrive) return Instruction{t_s, K::kArrived, 0};
  std::vector<int> on;
  double level = 0;
  for (const auto& c : p.commands) {
    if (c.level != 0) on.push_back(c.actuator);
    level = c.level;
  }
  switch (p.device) {
    case interaction::DeviceKind::kBelt: {
      if (on.size() != 1) return std::nullopt;
      // Vibrators from the left (+90 deg) to the right (-90 deg); the front one: keep going.
      static constexpr double kAngle[interaction::BeltAdapter::kCount] = {M_PI / 2, M_PI / 4, 0, -M_PI / 4, -M_PI / 2};
      if (on.front() == interaction::BeltAdapter::kFront) return Instruction{t_s, K::kKeepGoing, 0};
      return Instruction{t_s, K::kGo, kAngle[on.front()]};
    }
    case interaction::DeviceKind::kWheel:
      return Instruction{t_s, K::kSteer, on.empty() ? 0.0 : level * 1e-3};
    case interaction::DeviceKind::kRumble: {
      if (on.empty()) return Instruction{t_s, K::kClear, 0};
      if (on.size() == 2) return Instruction{t_s, K::kHalt, 0};
      return Instruction{t_s, K::kTurnToward, on.front() == interaction::RumbleAdapter::kLeft ? 1.0 : -1.0};
    }
    case interaction::DeviceKind::kHand:
      return std::nullopt;  // read from the cue's direction (hand_instruction)
  }
  return std::nullopt;
}

/// The hand unit's direction as the person moves the hand, in the hand frame (x right, y down,
/// z forward); zero for hold.
Vec3 hand_vector(planning::HandDirection d) {
  using D = planning::HandDirection;
  const double h = M_SQRT1_2;
  switch (d) {
    case D::kHold: return Vec3::Zero();
    case D::kRight: return Vec3(1, 0, 0);
    case D::kUpRight: return Vec3(h, -h, 0);
    case D::kUp: return Vec3(0, -1, 0);
    case D::kUpLeft: return Vec3(-h, -h, 0);
    case D::kLeft: return Vec3(-1, 0, 0);
    case D::kDownLeft: return Vec3(-h, h, 0);
    case D::kDown: return Vec3(0, 1, 0);
    case D::kDownRight: return Vec3(h, h, 0);
    case D::kForward: return Vec3(0, 0, 1);
    case D::kBackward: return Vec3(0, 0, -1);
  }
  return Vec3::Zero();
}

}  // namespace

std::optional<Instruction> perceive_cue(const interaction::CueEvent& ev, double t_s) {
  using interaction::CueOutcome;
  if (ev.outcome == CueOutcome::kSpoken && ev.cue.message) {
    const std::string& id = ev.cue.message->id;
    if (id == "stop") return Instruction{t_s, K::kStop, 0};
    if (id == "locating") return Instruction{t_s, K::kWait, 0};
    if (id == "arrived" || id == "target_reached") return Instruction{t_s, K::kArrived, 0};
    if (id == "arrived_facing") {
      // Heard as a clock position: the person turns to the middle of that hour.
      const auto clock = ev.cue.message->args.find("clock");
      const int hour = clock == ev.cue.message->args.end() ? 12 : std::atoi(clock->second.c_str());
      return Instruction{t_s, K::kArrived, interaction::clock_bearing(hour)};
    }
    return std::nullopt;
  }
  if (ev.outcome == CueOutcome::kSwitchedOff) return Instruction{t_s, K::kClear, 0};
  // A refresh repeats what is already felt, except the wheel, whose pull is read continuously, and
  // the belt's front vibrator, whose intermittent pulse means "walk forward" (§III-E) to a person
  // who stopped meanwhile (a side vibrator's refresh would turn them twice).
  // W-ROMA's hand unit repeats its command every two seconds, and each is a move of the hand.
  const bool continuous = ev.pattern && (ev.pattern->device == interaction::DeviceKind::kWheel ||
                                         ev.pattern->device == interaction::DeviceKind::kHand ||
                                         (ev.pattern->device == interaction::DeviceKind::kBelt &&
                                          ev.cue.kind == interaction::CueKind::kOnCourse));
  const bool fresh = ev.outcome == CueOutcome::kSent || (ev.outcome == CueOutcome::kRefreshed && continuous);
  if (!fresh || !ev.pattern || !ev.cue.felt) return std::nullopt;
  if (ev.pattern->device == interaction::DeviceKind::kHand && ev.cue.kind == CueKind::kObjectDirection) {
    if (!ev.cue.hand) return std::nullopt;
    Instruction i{t_s, K::kMoveHand, 0};
    i.hand_H = hand_vector(*ev.cue.hand);
    return i;
  }
  return felt(*ev.pattern, ev.cue.kind, t_s);
}

}  // namespace navaid::experiments
