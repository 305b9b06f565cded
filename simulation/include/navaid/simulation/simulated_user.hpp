#pragma once
// A simulated blind or low-vision user in closed loop (docs/simulated-users.md): what they do next
// depends on what their device told them and what their cane found. They perceive instructions
// after a reaction delay, follow each with a probability (compliance), turn with an error, walk at
// their own speed, veer while walking, and avoid what the cane touches. The device layer turns its
// cues into `Instruction`s as the person would read them (a belt motor, the wheel's pull, a rumble,
// a spoken word); this class knows nothing of devices.
#include <cstdint>
#include <deque>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "navaid/core/config.hpp"
#include "navaid/simulation/body_contacts.hpp"
#include "navaid/simulation/person_motion.hpp"

namespace navaid::simulation {

struct UserModel {
  std::string name = "typical";
  double speed_mps = 0.9;            ///< preferred walking speed (blind travellers with a device: 0.6-1.0)
  double speed_sigma_mps = 0.08;     ///< per-trial spread of the preferred speed
  double reaction_delay_s = 0.6;     ///< from a cue to the start of the response
  double reaction_jitter_s = 0.15;   ///< uniform +- spread of the delay
  double turn_error_sigma_rad = 0.09;  ///< heading error of a turn made on a cue (about 5 deg)
  double compliance = 0.95;          ///< probability that an instruction is followed
  double wheel_gain = 2.0;           ///< turn rate [rad/s] per radian of the steering wheel's pull
  double rumble_turn_rate_rad_s = 0.8;  ///< turning toward the open side while a side rumbles
  double rumble_speed_factor = 0.4;  ///< walking speed while a side rumbles
  double cane_stop_s = 0.6;          ///< pause after the cane touches something
  double cane_turn_rad = 1.0;        ///< turn away from what the cane touched (about 57 deg)
  double cane_detour_m = 0.8;        ///< walk this far before heading back to the intended way
  PersonMotionConfig motion;
  BodyModel body;
  CaneModel cane;
};

/// The documented presets: "typical", "cautious" (slower, later, no veer), "hasty" (faster, less
/// compliant, more veer), "sighted-blindfolded" (blindfolded sighted volunteers as in the seeds'
/// studies: slow, hesitant, veering, no cane training). UsageError listing them for another name.
UserModel user_model_preset(std::string_view name);
std::vector<std::string> user_model_names();
/// The preset `user.model` (default "typical") with any user.* key of `config` applied.
UserModel read_user_model(const Config& config);

/// What a person makes of a cue.
struct Instruction {
  enum class Kind {
    kGo,         ///< walk in `value` [rad] relative to the current heading, positive left
    kKeepGoing,  ///< on course: keep walking as you are
    kSteer,      ///< the wheel pulls by `value` [rad], positive left (held until the next)
    kTurnToward, ///< a side rumbles: turn toward `value`'s sign (+1 left, -1 right) while it does
    kHalt,       ///< both sides rumble / an obstacle with no open side: stop and search
    kStop,       ///< stop
    kWait,       ///< "locating": stop until directions come again
    kArrived,    ///< the goal is reached; `value` [rad]: where the destination lies, 0 = not said
    kClear,      ///< the haptic pattern went off: whatever it said is over
    kMoveHand,   ///< move the hand along `hand_H` (W-ROMA's hand unit); zero: hold it there
  };
  double t_s = 0;
  Kind kind = Kind::kKeepGoing;
  double value = 0;
  /// kMoveHand: the direction in the hand frame (x right, y down, z forward: the camera's axes).
  Vec3 hand_H = Vec3::Zero();
};
std::string_view to_string(Instruction::Kind kind);

struct UserCounts {
  std::size_t instructions = 0;  ///< perceived
  std::size_t ignored = 0;       ///< not followed (compliance)
  std::size_t corrections = 0;   ///< direction changes acted on (go > 10 deg, side rumbles, halts)
  std::size_t stops = 0;
  std::size_t cane_avoidances = 0;  ///< detours started from a touch of the cane or of the body
  std::size_t bumps = 0;            ///< steps stopped by an obstacle the body ran into
};

class SimulatedUser {
 public:
  /// `goal_known` false: the person stands until the device gives its first direction and then
  /// walks as told (a route or a path the device knows). True: they walk toward `goal_W` from the
  /// start, as a traveller who knows where it lies or hears it (the BYU study's music source), and
  /// the device's cues turn or stop them only while they last (cane only, the augmented cane).
  SimulatedUser(const UserModel& model, bool goal_known, const Vec2& goal_W, std::uint64_t seed);
  /// As above, with the route's turns known (an orientation-and-mobility briefing: "right after
  /// the chairs, then left"): a goal-known person walks to each turn point in order, then to the
  /// goal. A turn point counts as passed within `reach_m`, or once the person is past it along
  /// the next leg and within 2 reach_m.
  SimulatedUser(const UserModel& model, bool goal_known, std::vector<Vec2> turns_then_goal, double reach_m,
                std::uint64_t seed);

  /// A guided person who walks off along `heading_rad` at `speed_factor` of their speed until the
  /// device's first direction, instead of standing (a "locating" message does not hold them; a stop
  /// does): eLabrador's users, placed at the start facing the route, walk the first street so that
  /// GPS and the walked track can be registered.
  void walk_off(double heading_rad, double speed_factor) { walk_off_ = std::make_pair(heading_rad, speed_factor); }

  /// A goal-known person who stops at the goal as they know it (within the turn points' reach of
  /// it) and says they have arrived, instead of walking on toward it: eLabrador's cane users, whose
  /// trial ends where they stop.
  void stop_at_goal() { stop_at_goal_ = true; }

  /// The experimenter turns the person to `heading_W` and lets them walk on (a correction): a
  /// guided person walks that way until the device's next direction; a goal-known one walks it for
  /// `distance_m`, then heads for their goal again.
  void redirect(double heading_W, double distance_m, const PersonMotion& body);

  /// An instruction the device gave at i.t_s; acted on after the reaction delay.
  void perceive(const Instruction& i);

  /// What the person does over the next step at time t, from where they are and what the cane
  /// feels (may be empty).
  /// `bump`: the body ran into something on the last step (ContactMonitor::bump); handled as a
  /// cane touch, with or without a cane.
  MotionCommand decide(double t_s, const PersonMotion& body, const std::optional<CaneTouch>& cane,
                       const std::optional<CaneTouch>& bump = std::nullopt);

  bool arrived() const { return arrived_; }
  std::size_t turns_passed() const { return next_way_; }
  double preferred_speed() const { return speed_; }
  const UserCounts& counts() const { return counts_; }
  const UserModel& model() const { return model_; }

 private:
  void act(const Instruction& i, const PersonMotion& body);
  /// Where a goal-known person heads now: the next turn point not yet passed, or the goal.
  const Vec2& aim(const Vec2& position);

  UserModel model_;
  bool goal_known_;
  Vec2 goal_W_;
  std::vector<Vec2> way_;        ///< turn points then the goal
  std::size_t next_way_ = 0;
  double reach_m_ = 0.8;
  std::mt19937_64 rng_;
  double speed_ = 0;
  std::deque<Instruction> pending_;  ///< perceived, to be acted on at their t_s (delay added)
  // What the person is doing.
  enum class Mode { kStanding, kWalkHeading, kSteer, kTurnToward, kSearch, kArrived };
  Mode mode_ = Mode::kStanding;
  double heading_ = 0, steer_ = 0, turn_side_ = 0;
  double speed_factor_ = 1.0;
  bool started_ = false, arrived_ = false;
  std::optional<std::pair<double, double>> walk_off_;  ///< heading, speed factor
  bool stopped_before_start_ = false;
  bool stop_at_goal_ = false;
  bool facing_set_ = false;  ///< told on arrival which way the destination lies
  // Avoiding what the cane touched: paused until, then walking the detour heading until the
  // distance walked passes detour_end.
  std::optional<double> pause_until_;
  std::optional<double> detour_heading_;
  double detour_end_m_ = 0;
  double avoid_side_ = 1.0;      ///< +1: turning left, away from a touch on the right
  bool new_direction_ = false;   ///< acted on a new direction since the last decide()
  UserCounts counts_;
};

}  // namespace navaid::simulation
