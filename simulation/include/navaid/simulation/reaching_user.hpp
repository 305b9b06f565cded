#pragma once
// A simulated person searching for an object with the hand (W-ROMA's task, seed
// w-roma-rgbd-vio-object-manipulation §VI-B; docs/simulated-users.md "Reaching"). Two ways:
//
// Guided by the hand unit (perceive()): each direction cue, after the person's reaction delay and
// if followed (compliance), moves the hand along it, in error by direction_sigma, for
// move_time_s (the motor vibrates one second). The person reads the unit's directions in the
// walking frame: right / left sideways, up / down vertically, forward / backward along the
// walking heading. A cue that turns the hand back halves the length of the moves (down to 2 cm: the
// person overshot and now moves finely); cues that repeat a direction lengthen them again (x 1.5).
// Where the arm cannot go on, the body does: "forward" with the arm out starts a walk at
// step_speed_mps that goes on while the cues say forward; a side cue while walking, with the arm
// out (pointing: the shoulder turns) or with the hand at its side's limit stops the walk and turns
// the body by up to turn_rad (halved when the side flips, down to 3 deg, grown again while it
// repeats; the error at most 0.3 of the turn: small turns are made finely); any other cue stops
// the walk. "Backward" with the hand drawn in to the chest turns the person round (the object is
// behind them; the paper's rule says backward whenever it is behind the hand's plane). "Hold" stops
// the hand; "target reached" (kArrived) makes the person grasp; "locating" / stop hold everything.
// Walking into something (a table's edge), they trail along it (detour_rad for detour_m) toward
// the side the unit last pointed to, the other way if that is blocked at once, and stand to reach
// if both are; then face the way they walked again. Until they walk free of it (0.5 m without a
// bump), "forward" with the arm out does nothing and a side cue with the arm out is a 0.3 m step
// along the edge toward that side.
//
// From memory, without a device (search_from_memory()): the person touched the object before
// being led away (the paper's protocol) and remembers where it is with an error (the trial draws
// it); they walk toward the remembered place until it is within the arm's reach, then sweep the
// hand in an outward spiral (rings sweep_spacing_m apart) at the remembered height, walking and
// turning as the spiral leaves the arm's reach. A body that runs into something steps aside
// (detour_rad for detour_m) and goes on.
#include <cstdint>
#include <deque>
#include <optional>
#include <random>

#include "navaid/simulation/hand_motion.hpp"
#include "navaid/simulation/simulated_user.hpp"

namespace navaid::simulation {

struct ReachModel {
  double move_time_s = 1.0;             ///< a direction cue moves the hand this long (W-ROMA: 1 s of vibration)
  double direction_sigma_rad = 0.2;     ///< error of the direction the hand moves in
  double step_speed_mps = 0.5;          ///< walking on "forward" with the arm out
  double turn_rad = 0.26;               ///< turn on a side cue when the arm cannot go on (15 deg)
  double search_speed_mps = 0.45;       ///< walking to the remembered place (blindfolded, hesitant)
  double sweep_spacing_m = 0.15;        ///< between the rings of the hand's search spiral
  double detour_rad = 1.4;              ///< trailing along what the body ran into (80 deg)
  double detour_m = 0.5;
};

/// Keys user.reach.*: move_time_s (0.1, 5], direction_sigma_deg [0, 90], step_speed_mps (0.05, 1.5],
/// turn_deg [2, 90], search_speed_mps (0.05, 1.5], sweep_spacing_m [0.03, 1], detour_deg [10, 120],
/// detour_m [0.1, 3]. ConfigError naming the key when out of range.
ReachModel read_reach_model(const Config& config);

struct ReachCounts {
  std::size_t hand_cues = 0;  ///< perceived
  std::size_t ignored = 0;    ///< not followed (compliance)
  std::size_t walks = 0;      ///< forward cues walked (the arm was out)
  std::size_t turns = 0;      ///< side cues turned (the hand was at its side's limit)
  std::size_t grasps = 0;     ///< closed the hand on "target reached"
  std::size_t detours = 0;    ///< stepped aside after running into something
  std::size_t rings = 0;      ///< spiral rings swept (from memory)
};

class ReachingUser {
 public:
  /// `user`: reaction delay, jitter and compliance, turn error; `reach`: as above.
  ReachingUser(const UserModel& user, const ReachModel& reach, std::uint64_t seed);

  /// A cue of the hand unit (kMoveHand, kArrived, kWait, kStop; others are ignored).
  void perceive(const Instruction& i);
  /// Search without a device for the object remembered at `remembered_W` (its touched face).
  void search_from_memory(const Vec3& remembered_W);

  struct Decision {
    MotionCommand body;
    bool grasp = false;  ///< closes the hand now
  };
  /// The next step: moves `hand`'s target, says what the body does. `bumped`: the body ran into
  /// something on the last step. `mount_z`: the hand's height at rest offset 0 in W.
  Decision decide(double t_s, const PersonMotion& body, HandMotion& hand, double mount_z, bool bumped);

  const ReachCounts& counts() const { return counts_; }

 private:
  void act(const Instruction& i, const PersonMotion& body, HandMotion& hand);
  Decision sweep(const PersonMotion& body, HandMotion& hand, double mount_z, double dt, bool bumped);
  /// A spiral point the body cannot bring the hand to within this is given up [s].
  static constexpr double kGiveUpPointS = 4.0;

  UserModel user_;
  ReachModel reach_;
  std::mt19937_64 rng_;
  std::deque<Instruction> pending_;
  // Guided: walking on forward cues, along a heading.
  bool walking_ = false;
  std::optional<double> heading_;
  bool grasp_ = false;
  std::optional<Vec3> last_move_;  ///< the direction of the hand's last move (walking frame)
  double move_m_ = 0;              ///< the length of the next move
  static constexpr double kFinestMoveM = 0.02;
  double turn_now_ = 0, last_turn_side_ = 0;  ///< the next side turn and the side of the last
  static constexpr double kFinestTurnRad = 0.05;  ///< 3 deg
  double bump_side_ = 1.0;
  double last_side_ = 0.0;        ///< +1 left, -1 right: the side the last side cue pointed to
  double detour_start_m_ = 0;
  bool flipped_ = false;          ///< the detour turned to the other side after a bump at once
  bool against_edge_ = false;     ///< ran into something and has not walked free since
  double free_from_m_ = 0;        ///< distance walked at the last bump
  static constexpr double kEdgeStepM = 0.3;  ///< a step along an edge on a side cue
  static constexpr double kFreeWalkM = 0.5;  ///< walked this far without a bump: free of the edge
  // From memory.
  std::optional<Vec3> remembered_W_;
  bool sweeping_ = false;
  double theta_ = 0;  ///< the spiral's angle
  double stuck_s_ = 0;  ///< since the hand last reached a spiral point
  double last_t_ = 0;
  std::optional<double> detour_heading_;
  double detour_end_m_ = 0;
  ReachCounts counts_;
};

}  // namespace navaid::simulation
