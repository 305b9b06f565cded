#include "navaid/simulation/reaching_user.hpp"

#include "navaid/core/random_draws.hpp"
#include "navaid/simulation/config_schema.hpp"

#include <algorithm>
#include <cmath>

namespace navaid::simulation {

namespace {

constexpr double kDeg = M_PI / 180.0;


}  // namespace

namespace {
const ReachModel kDefaults;
const ConfigKey<double> kMoveTime{"user.reach.move_time_s", kDefaults.move_time_s, {0.1, 5.0},
                                  "a direction cue moves the hand this long [s]"};
const ConfigKey<double> kDirectionSigma{"user.reach.direction_sigma_deg", kDefaults.direction_sigma_rad / kDeg,
                                        {0.0, 90.0}, "error of the direction the hand moves in [deg]"};
const ConfigKey<double> kStepSpeed{"user.reach.step_speed_mps", kDefaults.step_speed_mps, {0.05, 1.5},
                                   "walking speed on forward with the arm out [m/s]"};
const ConfigKey<double> kTurn{"user.reach.turn_deg", kDefaults.turn_rad / kDeg, {2.0, 90.0},
                              "turn on a side cue when the arm cannot go on [deg]"};
const ConfigKey<double> kSearchSpeed{"user.reach.search_speed_mps", kDefaults.search_speed_mps, {0.05, 1.5},
                                     "walking speed to the remembered place [m/s]"};
const ConfigKey<double> kSweepSpacing{"user.reach.sweep_spacing_m", kDefaults.sweep_spacing_m, {0.03, 1.0},
                                      "spacing of the rings of the hand's search spiral [m]"};
const ConfigKey<double> kDetourAngle{"user.reach.detour_deg", kDefaults.detour_rad / kDeg, {10.0, 120.0},
                                     "turn when trailing along what the body ran into [deg]"};
const ConfigKey<double> kDetour{"user.reach.detour_m", kDefaults.detour_m, {0.1, 3.0},
                                "distance trailed along what the body ran into [m]"};
}  // namespace

ConfigSchema reach_model_schema() {
  return ConfigSchema()
      .add(kMoveTime)
      .add(kDirectionSigma)
      .add(kStepSpeed)
      .add(kTurn)
      .add(kSearchSpeed)
      .add(kSweepSpacing)
      .add(kDetourAngle)
      .add(kDetour);
}

ReachModel read_reach_model(const Config& c) {
  ReachModel m;
  m.move_time_s = get(c, kMoveTime);
  m.direction_sigma_rad = get(c, kDirectionSigma) * kDeg;
  m.step_speed_mps = get(c, kStepSpeed);
  m.turn_rad = get(c, kTurn) * kDeg;
  m.search_speed_mps = get(c, kSearchSpeed);
  m.sweep_spacing_m = get(c, kSweepSpacing);
  m.detour_rad = get(c, kDetourAngle) * kDeg;
  m.detour_m = get(c, kDetour);
  return m;
}

ReachingUser::ReachingUser(const UserModel& user, const ReachModel& reach, std::uint64_t seed)
    : user_(user), reach_(reach), rng_(seed) {}

void ReachingUser::perceive(const Instruction& i) {
  using K = Instruction::Kind;
  if (i.kind != K::kMoveHand && i.kind != K::kArrived && i.kind != K::kWait && i.kind != K::kStop) return;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  if (i.kind == K::kMoveHand) {
    ++counts_.hand_cues;
    if (u(rng_) > user_.compliance) {
      ++counts_.ignored;
      return;
    }
  }
  Instruction delayed = i;
  delayed.t_s = i.t_s + std::max(0.0, user_.reaction_delay_s + user_.reaction_jitter_s * (2.0 * u(rng_) - 1.0));
  if (!pending_.empty()) delayed.t_s = std::max(delayed.t_s, pending_.back().t_s);
  pending_.push_back(delayed);
}

void ReachingUser::search_from_memory(const Vec3& remembered_W) {
  remembered_W_ = remembered_W;
  sweeping_ = false;
  theta_ = 0;
}

void ReachingUser::act(const Instruction& i, const PersonMotion& body, HandMotion& hand) {
  using K = Instruction::Kind;
  if (i.kind == K::kArrived) {
    grasp_ = true;
    ++counts_.grasps;
  }
  if (i.kind != K::kMoveHand || i.hand_H.norm() < 1e-9) {  // hold, grasp, locating, stop: everything stops
    walking_ = false;
    hand.move_to(hand.offset());
    return;
  }
  // The unit's direction in the walking frame (x forward, y left, z up), as the person moves it.
  std::normal_distribution<double> n(0.0, reach_.direction_sigma_rad);
  Vec3 dir = Vec3(i.hand_H.z(), -i.hand_H.x(), -i.hand_H.y()).normalized();
  dir = (dir + draw_vector<3>([&] { return n(rng_); })).normalized();
  const Vec3 size = dir.cwiseAbs();
  const int dominant = size.x() >= size.y() && size.x() >= size.z() ? 0 : size.y() >= size.z() ? 1 : 2;
  const double side = dir.y() >= 0 ? 1.0 : -1.0;
  if (dominant == 1) last_side_ = side;
  // Against an edge (the body ran into it and has not walked free since), a side cue with the arm
  // out is a step along the edge: the person trails it toward the object.
  if (against_edge_ && dominant == 1 && hand.at_limit(0, 1.0, 0.1)) {
    walking_ = false;
    detour_heading_ = wrap_angle(heading_.value_or(body.heading()) + side * reach_.detour_rad);
    detour_start_m_ = body.distance_walked();
    detour_end_m_ = detour_start_m_ + kEdgeStepM;
    flipped_ = false;
    ++counts_.detours;
    return;
  }
  if (dominant == 0 && dir.x() > 0 && against_edge_ && hand.at_limit(0, 1.0, 0.03)) return;  // cannot go on
  if (dominant == 0 && dir.x() > 0 && (walking_ || hand.at_limit(0, 1.0, 0.03))) {  // the arm is out: walk on
    if (!walking_) ++counts_.walks;
    walking_ = true;
    heading_ = body.heading();
    return;
  }
  // A side cue turns the body while walking, with the arm out (pointing: the shoulder turns), or
  // with the hand at its side's limit. Turns halve when the side flips (overshot) and grow back
  // while it repeats, as the hand's moves do.
  if (dominant == 1 && (walking_ || hand.at_limit(0, 1.0, 0.1) || hand.at_limit(1, side, 0.03))) {
    ++counts_.turns;
    turn_now_ = last_turn_side_ == 0.0 ? reach_.turn_rad
                : last_turn_side_ != side ? std::max(kFinestTurnRad, 0.5 * turn_now_)
                                          : std::min(reach_.turn_rad, 1.5 * turn_now_);
    last_turn_side_ = side;
    std::normal_distribution<double> turn_error(0.0, std::min(user_.turn_error_sigma_rad, 0.3 * turn_now_));
    heading_ = wrap_angle(body.heading() + side * turn_now_ + turn_error(rng_));
    walking_ = false;  // a blindfolded walker stops to turn
    return;
  }
  walking_ = false;
  if (dominant == 0 && dir.x() < 0 && hand.at_limit(0, -1.0, 0.03)) {
    // "Backward" with the hand at the chest: the object is behind; the person turns round to it.
    ++counts_.turns;
    std::uniform_int_distribution<int> coin(0, 1);
    std::normal_distribution<double> turn_error(0.0, user_.turn_error_sigma_rad);
    heading_ = wrap_angle(body.heading() + (coin(rng_) ? M_PI : -M_PI) + turn_error(rng_));
    hand.move_to(hand.config().rest_offset_m);
    return;
  }
  // The move's length: a full move's, halved each time a cue turns the hand back (the person
  // overshot) and grown again while cues repeat a direction.
  const double full = hand.config().speed_mps * reach_.move_time_s;
  if (last_move_) {
    const double agree = dir.dot(*last_move_);
    if (agree < -0.3) move_m_ = std::max(kFinestMoveM, 0.5 * move_m_);
    if (agree > 0.7) move_m_ = std::min(full, 1.5 * move_m_);
  } else {
    move_m_ = full;
  }
  last_move_ = dir;
  hand.move_to(hand.offset() + dir * move_m_);
}

ReachingUser::Decision ReachingUser::decide(double t_s, const PersonMotion& body, HandMotion& hand, double mount_z,
                                            bool bumped) {
  const double dt = std::max(0.0, t_s - last_t_);
  last_t_ = t_s;
  while (!pending_.empty() && pending_.front().t_s <= t_s) {
    act(pending_.front(), body, hand);
    pending_.pop_front();
  }
  Decision d;
  d.body.heading_rad = heading_.value_or(body.heading());
  if (remembered_W_) return sweep(body, hand, mount_z, dt, bumped);
  // Walking on "forward" into something (a table's edge): trail along it toward the side the unit
  // last pointed to (either before any), the other way if that side is blocked at once, and stand
  // to reach if both are; then face the way walked again.
  if (bumped) {
    against_edge_ = true;
    free_from_m_ = body.distance_walked();
  } else if (against_edge_ && body.distance_walked() - free_from_m_ > kFreeWalkM && walking_) {
    against_edge_ = false;  // walked free of it
  }
  if (bumped && (walking_ || detour_heading_)) {
    const bool blocked_at_once = detour_heading_ && body.distance_walked() - detour_start_m_ < 0.1;
    if (blocked_at_once && flipped_) {
      detour_heading_.reset();
    } else {
      if (blocked_at_once) {
        bump_side_ = -bump_side_;
      } else {
        std::uniform_int_distribution<int> coin(0, 1);
        bump_side_ = last_side_ != 0.0 ? last_side_ : coin(rng_) ? 1.0 : -1.0;
      }
      flipped_ = blocked_at_once;
      detour_heading_ = wrap_angle(heading_.value_or(body.heading()) + bump_side_ * reach_.detour_rad);
      detour_start_m_ = body.distance_walked();
      detour_end_m_ = detour_start_m_ + reach_.detour_m;
      ++counts_.detours;
    }
    walking_ = false;
  }
  if (detour_heading_) {
    if (body.distance_walked() < detour_end_m_) {
      d.body.heading_rad = *detour_heading_;
      // Turn along the edge first, then step.
      if (std::abs(wrap_angle(*detour_heading_ - body.heading())) < 0.3) d.body.speed_mps = reach_.step_speed_mps;
      return d;
    }
    detour_heading_.reset();
  }
  if (walking_) d.body.speed_mps = reach_.step_speed_mps;
  d.grasp = grasp_;
  grasp_ = false;
  return d;
}

ReachingUser::Decision ReachingUser::sweep(const PersonMotion& body, HandMotion& hand, double mount_z, double dt,
                                           bool bumped) {
  Decision d;
  d.body.heading_rad = body.heading();
  const Vec3& m = *remembered_W_;
  const Vec2 p = body.position();
  if (detour_heading_) {
    if (body.distance_walked() < detour_end_m_) {
      d.body.heading_rad = *detour_heading_;
      d.body.speed_mps = reach_.search_speed_mps;
      return d;
    }
    detour_heading_.reset();
  }
  const double arm = hand.config().max_offset_m.x() - 0.1;  // comfortably within reach
  const auto bump_aside = [&] {
    std::uniform_int_distribution<int> coin(0, 1);
    detour_heading_ = wrap_angle(body.heading() + (coin(rng_) ? 1.0 : -1.0) * reach_.detour_rad);
    detour_end_m_ = body.distance_walked() + reach_.detour_m;
    ++counts_.detours;
  };
  if (!sweeping_) {
    const Vec2 to = m.head<2>() - p;
    if (to.norm() > arm) {  // walk to the remembered place, the hand at rest before the chest
      if (bumped) bump_aside();
      d.body.heading_rad = std::atan2(to.y(), to.x());
      d.body.speed_mps = reach_.search_speed_mps;
      hand.move_to(hand.config().rest_offset_m);
      return d;
    }
    sweeping_ = true;
    theta_ = 0;
    stuck_s_ = 0;
  }
  // The spiral's point now, as an offset of the hand from the body.
  const double a = reach_.sweep_spacing_m / (2.0 * M_PI);
  const double r = a * theta_;
  const Vec3 point(m.x() + r * std::cos(theta_), m.y() + r * std::sin(theta_), m.z());
  const double psi = body.heading();
  const Mat3 R = Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 wanted = R.transpose() * (point - Vec3(p.x(), p.y(), mount_z));
  hand.move_to(wanted);
  const bool reachable = (hand.target() - wanted).norm() < 1e-6;
  if (!reachable) {  // the spiral left the arm's reach: turn toward the point, and step when it is far
    const Vec2 to = point.head<2>() - p;
    d.body.heading_rad = std::atan2(to.y(), to.x());
    d.body.speed_mps = to.norm() > arm ? 0.5 * reach_.search_speed_mps : 0.0;
    if (bumped) bump_aside();
  }
  // Onward along the spiral at the hand's speed once the hand is at the point; a point the body
  // cannot get to within a few seconds (behind a table) is given up.
  stuck_s_ += dt;
  if ((reachable && (hand.offset() - wanted).norm() < 0.03) || stuck_s_ > kGiveUpPointS) {
    theta_ += hand.config().speed_mps * dt / std::max(r, reach_.sweep_spacing_m);
    if (stuck_s_ > kGiveUpPointS) theta_ += 0.5;
    stuck_s_ = 0;
  }
  counts_.rings = static_cast<std::size_t>(theta_ / (2.0 * M_PI));
  return d;
}

}  // namespace navaid::simulation
