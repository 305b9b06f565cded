#include "navaid/simulation/simulated_user.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/config_schema.hpp"

namespace navaid::simulation {

namespace {

constexpr double kDeg = M_PI / 180.0;


}  // namespace

std::string_view to_string(Instruction::Kind kind) {
  switch (kind) {
    case Instruction::Kind::kGo: return "go";
    case Instruction::Kind::kKeepGoing: return "keep-going";
    case Instruction::Kind::kSteer: return "steer";
    case Instruction::Kind::kTurnToward: return "turn-toward";
    case Instruction::Kind::kHalt: return "halt";
    case Instruction::Kind::kStop: return "stop";
    case Instruction::Kind::kWait: return "wait";
    case Instruction::Kind::kArrived: return "arrived";
    case Instruction::Kind::kClear: return "clear";
    case Instruction::Kind::kMoveHand: return "move-hand";
  }
  return "?";
}

std::vector<std::string> user_model_names() { return {"typical", "cautious", "hasty", "sighted-blindfolded"}; }

UserModel user_model_preset(std::string_view name) {
  UserModel m;
  m.name = std::string(name);
  m.motion.veer_sigma = 1.5 * kDeg;  // a few degrees of heading error after ten seconds' walk
  if (name == "typical") return m;
  if (name == "cautious") {
    m.speed_mps = 0.65;
    m.reaction_delay_s = 0.9;
    m.turn_error_sigma_rad = 4 * kDeg;
    m.compliance = 0.99;
    m.motion.veer_sigma = 0.0;
    return m;
  }
  if (name == "hasty") {
    m.speed_mps = 1.2;
    m.reaction_delay_s = 0.4;
    m.turn_error_sigma_rad = 9 * kDeg;
    m.compliance = 0.85;
    m.motion.veer_sigma = 3.0 * kDeg;
    return m;
  }
  if (name == "sighted-blindfolded") {
    m.speed_mps = 0.7;
    m.speed_sigma_mps = 0.12;
    m.reaction_delay_s = 1.0;
    m.reaction_jitter_s = 0.3;
    m.turn_error_sigma_rad = 10 * kDeg;
    m.compliance = 0.9;
    m.motion.veer_sigma = 4.0 * kDeg;
    m.cane.sweep_half_angle_rad = 0.3;  // an untrained, narrow sweep
    return m;
  }
  throw UsageError(fmt::format("unknown user model '{}' (known: {})", name, fmt::join(user_model_names(), ", ")));
}

namespace {
// Defaults come from the user model (user.model), so the keys declare none.
const ConfigKey<double> kSpeedMps{"user.speed_mps", std::nullopt, {0.2, 2.0},
    "walking speed [m/s]; default: the user model's"};
const ConfigKey<double> kSpeedSigmaMps{"user.speed_sigma_mps", std::nullopt, {0.0, 0.5},
    "spread of the walking speed between users [m/s]; default: the user model's"};
const ConfigKey<double> kReactionDelayS{"user.reaction_delay_s", std::nullopt, {0.0, 5.0},
    "delay from a cue to the reaction [s]; default: the user model's"};
const ConfigKey<double> kReactionJitterS{"user.reaction_jitter_s", std::nullopt, {0.0, 2.0},
    "spread of the reaction delay [s]; default: the user model's"};
const ConfigKey<double> kTurnErrorSigmaDeg{"user.turn_error_sigma_deg", std::nullopt, {0.0, 45.0},
    "error of a turn made on a cue [deg]; default: the user model's"};
const ConfigKey<double> kCompliance{"user.compliance", std::nullopt, {0.0, 1.0},
    "share of cues followed; default: the user model's"};
const ConfigKey<double> kWheelGain{"user.wheel_gain", std::nullopt, {0.1, 10.0},
    "how strongly the user follows the steering wheel; default: the user model's"};
const ConfigKey<double> kRumbleTurnRateDegS{"user.rumble_turn_rate_deg_s", std::nullopt, {5.0, 180.0},
    "turn rate while a rumble remote vibrates [deg/s]; default: the user model's"};
const ConfigKey<double> kRumbleSpeedFactor{"user.rumble_speed_factor", std::nullopt, {0.0, 1.0},
    "walking speed factor while a rumble remote vibrates; default: the user model's"};
const ConfigKey<double> kCaneStopS{"user.cane_stop_s", std::nullopt, {0.0, 5.0},
    "stop after the cane touches something [s]; default: the user model's"};
const ConfigKey<double> kCaneTurnDeg{"user.cane_turn_deg", std::nullopt, {10.0, 120.0},
    "turn away from what the cane touched [deg]; default: the user model's"};
const ConfigKey<double> kCaneDetourM{"user.cane_detour_m", std::nullopt, {0.1, 5.0},
    "detour walked around what the cane touched [m]; default: the user model's"};
const ConfigKey<double> kMotionStepLengthM{"user.motion.step_length_m", std::nullopt, {0.2, 1.5},
    "step length [m]; default: the user model's"};
const ConfigKey<double> kMotionVeerSigmaDeg{"user.motion.veer_sigma_deg", std::nullopt, {0.0, 20.0},
    "veer of a walk without cues [deg]; default: the user model's"};
const ConfigKey<double> kMotionVeerTimeConstantS{"user.motion.veer_time_constant_s", std::nullopt, {0.5, 100.0},
    "time constant of the veer [s]; default: the user model's"};
const ConfigKey<double> kMotionMaxTurnRateDegS{"user.motion.max_turn_rate_deg_s", std::nullopt, {10.0, 360.0},
    "largest turn rate [deg/s]; default: the user model's"};
const ConfigKey<double> kBodyRadiusM{"user.body.radius_m", std::nullopt, {0.1, 0.5},
    "radius of the body [m]; default: the user model's"};
const ConfigKey<double> kBodyHeightM{"user.body.height_m", std::nullopt, {1.2, 2.2},
    "height of the body [m]; default: the user model's"};
const ConfigKey<bool> kCaneEnabled{"user.cane.enabled", std::nullopt, "the user sweeps a long cane; default: the user model's"};
const ConfigKey<double> kCaneLengthM{"user.cane.length_m", std::nullopt, {0.5, 1.8},
    "length of the cane [m]; default: the user model's"};
const ConfigKey<double> kCaneSweepHalfAngleDeg{"user.cane.sweep_half_angle_deg", std::nullopt, {0.0, 75.0},
    "half-angle of the cane's sweep [deg]; default: the user model's"};
const ConfigKey<double> kCaneDetectHeightM{"user.cane.detect_height_m", std::nullopt, {0.05, 1.0},
    "the cane finds obstacles up to this height [m]; default: the user model's"};
const ConfigKey<std::string>& model_key() {
  static const ConfigKey<std::string> key{"user.model", std::string("typical"), user_model_names(),
                                          "the simulated user's preset (the user.* keys change it)"};
  return key;
}
}  // namespace

ConfigSchema user_model_schema() {
  ConfigSchema s;
  s.add(model_key());
  s.add(kSpeedMps);
  s.add(kSpeedSigmaMps);
  s.add(kReactionDelayS);
  s.add(kReactionJitterS);
  s.add(kTurnErrorSigmaDeg);
  s.add(kCompliance);
  s.add(kWheelGain);
  s.add(kRumbleTurnRateDegS);
  s.add(kRumbleSpeedFactor);
  s.add(kCaneStopS);
  s.add(kCaneTurnDeg);
  s.add(kCaneDetourM);
  s.add(kMotionStepLengthM);
  s.add(kMotionVeerSigmaDeg);
  s.add(kMotionVeerTimeConstantS);
  s.add(kMotionMaxTurnRateDegS);
  s.add(kBodyRadiusM);
  s.add(kBodyHeightM);
  s.add(kCaneEnabled);
  s.add(kCaneLengthM);
  s.add(kCaneSweepHalfAngleDeg);
  s.add(kCaneDetectHeightM);
  return s;
}

UserModel read_user_model(const Config& c) {
  UserModel m = user_model_preset(get(c, model_key()));
  const auto d = [&c](const ConfigKey<double>& key, double& v) { v = get(c, defaulting_to(key, v)); };
  const auto deg = [&c](const ConfigKey<double>& key, double& v) { v = get(c, defaulting_to(key, v / kDeg)) * kDeg; };
  d(kSpeedMps, m.speed_mps);
  d(kSpeedSigmaMps, m.speed_sigma_mps);
  d(kReactionDelayS, m.reaction_delay_s);
  d(kReactionJitterS, m.reaction_jitter_s);
  deg(kTurnErrorSigmaDeg, m.turn_error_sigma_rad);
  d(kCompliance, m.compliance);
  d(kWheelGain, m.wheel_gain);
  deg(kRumbleTurnRateDegS, m.rumble_turn_rate_rad_s);
  d(kRumbleSpeedFactor, m.rumble_speed_factor);
  d(kCaneStopS, m.cane_stop_s);
  deg(kCaneTurnDeg, m.cane_turn_rad);
  d(kCaneDetourM, m.cane_detour_m);
  d(kMotionStepLengthM, m.motion.step_length_m);
  deg(kMotionVeerSigmaDeg, m.motion.veer_sigma);
  d(kMotionVeerTimeConstantS, m.motion.veer_time_constant_s);
  deg(kMotionMaxTurnRateDegS, m.motion.max_turn_rate_rad_s);
  d(kBodyRadiusM, m.body.radius_m);
  d(kBodyHeightM, m.body.height_m);
  m.cane.enabled = get(c, defaulting_to(kCaneEnabled, m.cane.enabled));
  d(kCaneLengthM, m.cane.length_m);
  deg(kCaneSweepHalfAngleDeg, m.cane.sweep_half_angle_rad);
  d(kCaneDetectHeightM, m.cane.detect_height_m);
  validate(m.body);
  validate(m.cane);
  validate(m.motion);
  return m;
}

SimulatedUser::SimulatedUser(const UserModel& model, bool goal_known, const Vec2& goal_W, std::uint64_t seed)
    : SimulatedUser(model, goal_known, std::vector<Vec2>{goal_W}, 0.8, seed) {}

SimulatedUser::SimulatedUser(const UserModel& model, bool goal_known, std::vector<Vec2> turns_then_goal,
                             double reach_m, std::uint64_t seed)
    : model_(model), goal_known_(goal_known), way_(std::move(turns_then_goal)), reach_m_(reach_m), rng_(seed) {
  if (way_.empty()) throw std::invalid_argument("SimulatedUser: the way needs at least the goal");
  if (!(reach_m_ > 0)) throw std::invalid_argument("SimulatedUser: the turn points' reach must be positive");
  goal_W_ = way_.back();
  std::normal_distribution<double> n(model_.speed_mps, model_.speed_sigma_mps);
  speed_ = std::clamp(n(rng_), 0.3, 2.0);
}

const Vec2& SimulatedUser::aim(const Vec2& p) {
  while (next_way_ + 1 < way_.size()) {
    const Vec2& w = way_[next_way_];
    const Vec2 leg = way_[next_way_ + 1] - w;
    const bool reached = (p - w).norm() <= reach_m_;
    const bool past = (p - w).dot(leg) > 0 && (p - w).norm() <= 2 * reach_m_;
    if (!reached && !past) break;
    ++next_way_;
  }
  return way_[next_way_];
}

void SimulatedUser::perceive(const Instruction& i) {
  ++counts_.instructions;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Stop and arrival are always heeded; a direction may be missed or disregarded.
  const bool must = i.kind == Instruction::Kind::kStop || i.kind == Instruction::Kind::kArrived ||
                    i.kind == Instruction::Kind::kClear;
  if (!must && u(rng_) > model_.compliance) {
    ++counts_.ignored;
    return;
  }
  const double jitter = model_.reaction_jitter_s * (2.0 * u(rng_) - 1.0);
  Instruction delayed = i;
  delayed.t_s = i.t_s + std::max(0.0, model_.reaction_delay_s + jitter);
  // Acted on in time order (a later cue with a shorter jitter waits for the earlier one).
  if (!pending_.empty()) delayed.t_s = std::max(delayed.t_s, pending_.back().t_s);
  pending_.push_back(delayed);
}

void SimulatedUser::act(const Instruction& i, const PersonMotion& body) {
  std::normal_distribution<double> turn_error(0.0, model_.turn_error_sigma_rad);
  using K = Instruction::Kind;
  if (i.kind == K::kArrived) {
    // Stop; told where the destination lies ("at 9 o'clock"), turn to face it (heard again: again).
    mode_ = Mode::kArrived;
    arrived_ = true;
    if (i.value != 0.0) heading_ = wrap_angle(body.heading() + i.value + turn_error(rng_));
    else if (!facing_set_) heading_ = body.heading();
    facing_set_ = facing_set_ || i.value != 0.0;
    return;
  }
  if (mode_ == Mode::kArrived) return;
  switch (i.kind) {
    case K::kGo: {
      started_ = true;
      const double target = wrap_angle(body.heading() + i.value + turn_error(rng_));
      if (std::abs(i.value) > 10 * kDeg) ++counts_.corrections;
      heading_ = target;
      mode_ = Mode::kWalkHeading;
      speed_factor_ = 1.0;
      break;
    }
    case K::kKeepGoing:
      started_ = true;
      if (mode_ != Mode::kWalkHeading) heading_ = body.heading();
      mode_ = Mode::kWalkHeading;
      speed_factor_ = 1.0;
      break;
    case K::kSteer:
      started_ = true;
      steer_ = i.value;
      mode_ = Mode::kSteer;
      speed_factor_ = 1.0;
      break;
    case K::kTurnToward:
      started_ = true;
      if (mode_ != Mode::kTurnToward || turn_side_ != (i.value >= 0 ? 1.0 : -1.0)) ++counts_.corrections;
      turn_side_ = i.value >= 0 ? 1.0 : -1.0;
      mode_ = Mode::kTurnToward;
      speed_factor_ = model_.rumble_speed_factor;
      break;
    case K::kHalt:
      started_ = true;
      if (mode_ != Mode::kSearch) {
        ++counts_.corrections;
        ++counts_.stops;
        // Search for an open way: turn on the spot toward the side of where they are going.
        const Vec2 d = aim(body.position()) - body.position();
        turn_side_ = wrap_angle(std::atan2(d.y(), d.x()) - body.heading()) >= 0 ? 1.0 : -1.0;
      }
      mode_ = Mode::kSearch;
      break;
    case K::kWait:
      if (walk_off_ && !started_) break;  // walking off to be located, as told at the start
      [[fallthrough]];
    case K::kStop:
      if (!started_) stopped_before_start_ = true;
      if (mode_ != Mode::kStanding) ++counts_.stops;
      mode_ = Mode::kStanding;
      break;
    case K::kArrived: break;  // above
    case K::kClear:
      // A side rumble or a halt ended: walk on the way now faced.
      if (mode_ == Mode::kTurnToward || mode_ == Mode::kSearch) {
        heading_ = body.heading();
        mode_ = Mode::kWalkHeading;
        speed_factor_ = 1.0;
      }
      break;
    case K::kMoveHand: break;  // for the hand (reaching_user.hpp), not the walk
  }
  detour_heading_.reset();  // a fresh instruction supersedes a cane detour
  // A new direction from the device: the veer built up while walking the old one is gone.
  if (i.kind == K::kGo || i.kind == K::kSteer || i.kind == K::kTurnToward || i.kind == K::kHalt) new_direction_ = true;
}

void SimulatedUser::redirect(double heading_W, double distance_m, const PersonMotion& body) {
  if (mode_ == Mode::kArrived) return;
  started_ = true;
  pause_until_.reset();
  speed_factor_ = 1.0;
  new_direction_ = true;
  mode_ = Mode::kWalkHeading;
  heading_ = wrap_angle(heading_W);
  if (goal_known_) {
    detour_heading_ = heading_;
    detour_end_m_ = body.distance_walked() + distance_m;
  } else {
    detour_heading_.reset();
  }
}

namespace {
// A cane touch further than this off the walking line is something beside the way (a wall being
// walked along): the person edges away by kShorelineTurn instead of stopping to walk round it.
constexpr double kShorelineBearing = 0.3;
constexpr double kShorelineTurn = 0.35;
}  // namespace

MotionCommand SimulatedUser::decide(double t_s, const PersonMotion& body, const std::optional<CaneTouch>& cane_touch,
                                    const std::optional<CaneTouch>& bump) {
  while (!pending_.empty() && pending_.front().t_s <= t_s) {
    act(pending_.front(), body);
    pending_.pop_front();
  }
  MotionCommand c;
  if (walk_off_ && !goal_known_ && mode_ == Mode::kStanding && !started_ && !arrived_ && !stopped_before_start_) {
    mode_ = Mode::kWalkHeading;
    heading_ = walk_off_->first;
    speed_factor_ = walk_off_->second;
  }
  if (goal_known_ && mode_ == Mode::kStanding && !started_ && !arrived_) {
    // Walk toward the goal as one who knows where it lies (a stop holds them until the next cue).
    const Vec2 d = aim(body.position()) - body.position();
    heading_ = std::atan2(d.y(), d.x());
    mode_ = Mode::kWalkHeading;
    started_ = true;
  }
  if (goal_known_ && stop_at_goal_ && mode_ != Mode::kArrived && next_way_ + 1 == way_.size() &&
      (body.position() - goal_W_).norm() <= reach_m_) {
    // At the goal as they know it: they stop there, facing the way they came in.
    mode_ = Mode::kArrived;
    arrived_ = true;
    heading_ = body.heading();
    detour_heading_.reset();
    pause_until_.reset();
  }
  if (goal_known_ && mode_ == Mode::kWalkHeading && !detour_heading_) {
    const Vec2 d = aim(body.position()) - body.position();
    heading_ = std::atan2(d.y(), d.x());
  }
  // The cane, or the body itself walking into something: stop, turn away from it, walk a short
  // detour, then go on.
  const std::optional<CaneTouch> cane = bump ? bump : model_.cane.enabled ? cane_touch : std::nullopt;
  const bool moving_on = mode_ != Mode::kStanding && mode_ != Mode::kArrived && mode_ != Mode::kSearch;
  if (bump) ++counts_.bumps;
  if (cane && moving_on && !pause_until_) {
    ++counts_.cane_avoidances;
    avoid_side_ = cane->bearing_rad >= 0 ? -1.0 : 1.0;
    if (std::abs(cane->bearing_rad) > kShorelineBearing && !bump) {
      // Touched off to the side (a wall along the way, the shoreline): edge away without stopping.
      detour_heading_ = wrap_angle(body.heading() + avoid_side_ * kShorelineTurn);
      detour_end_m_ = body.distance_walked() + 0.5 * model_.cane_detour_m;
    } else {
      pause_until_ = t_s + model_.cane_stop_s;
      detour_heading_ = wrap_angle(body.heading() + avoid_side_ * model_.cane_turn_rad);
      detour_end_m_ = body.distance_walked() + model_.cane_detour_m;
    }
  } else if (pause_until_ && t_s >= *pause_until_) {
    if (cane) {
      // Still blocked after turning away: turn further the same way (a corner) and feel again.
      detour_heading_ = wrap_angle(*detour_heading_ + avoid_side_ * 0.5 * model_.cane_turn_rad);
      pause_until_ = t_s + model_.cane_stop_s;
    } else {
      pause_until_.reset();
      detour_end_m_ = body.distance_walked() + model_.cane_detour_m;
    }
  }
  if (detour_heading_ && !pause_until_ && body.distance_walked() >= detour_end_m_) detour_heading_.reset();

  switch (mode_) {
    case Mode::kStanding:
      c.speed_mps = 0;
      c.heading_rad = body.heading();
      break;
    case Mode::kArrived:
      c.speed_mps = 0;
      c.heading_rad = heading_;  // turning on the spot to face the destination, if told
      break;
    case Mode::kWalkHeading:
      c.speed_mps = speed_ * speed_factor_;
      c.heading_rad = heading_;
      break;
    case Mode::kSteer:
      c.speed_mps = speed_;
      c.follow_heading = false;
      c.turn_rate_rad_s = model_.wheel_gain * steer_;
      break;
    case Mode::kTurnToward:
      c.speed_mps = speed_ * speed_factor_;
      c.follow_heading = false;
      c.turn_rate_rad_s = turn_side_ * model_.rumble_turn_rate_rad_s;
      break;
    case Mode::kSearch:
      c.speed_mps = 0;
      c.follow_heading = false;
      c.turn_rate_rad_s = turn_side_ * model_.rumble_turn_rate_rad_s;
      break;
  }
  if (pause_until_) {
    // Turning away on the spot while paused, then the detour.
    c.speed_mps = 0;
    c.follow_heading = true;
    c.heading_rad = *detour_heading_;
  } else if (detour_heading_ && c.speed_mps > 0) {
    c.follow_heading = true;
    c.heading_rad = *detour_heading_;
  }
  c.new_direction = new_direction_;
  new_direction_ = false;
  return c;
}

}  // namespace navaid::simulation
