#pragma once
// Contacts of a simulated person with the world: the body (a vertical cylinder in three parts:
// legs, torso, head) and a long cane swept ahead of it, against every primitive of the static world
// and the moving people and vehicles. A contact is counted once when it begins (the part against a
// primitive it did not touch a moment ago), with the part hit and the height of the touch.
//
// The cane is the two-point-touch technique of orientation and mobility training: the tip touches
// the ground left and right of the walking line, one side per step, so the cane covers the sector
// ahead up to its length but finds only what reaches down to near the ground (a low box, a wall, a
// chair's legs); a sign board or a branch hanging at chest or head height passes over it. The
// augmented cane is swept the same way (its camera rides on the shaft). Both are `CaneModel`s.
#include <cstdint>
#include <optional>
#include <set>
#include <tuple>
#include <string_view>
#include <vector>

#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

enum class BodyPart { kLegs, kTorso, kHead, kCane };
std::string_view to_string(BodyPart part);

struct BodyModel {
  double radius_m = 0.22;       ///< half the shoulder width: the body's cylinder
  double height_m = 1.75;
  double step_over_m = 0.15;    ///< lower things are stepped over (curbs, the floor)
  double legs_top_m = 0.9;      ///< legs: [step_over, legs_top)
  double head_bottom_m = 1.5;   ///< torso: [legs_top, head_bottom); head: [head_bottom, height]
};

struct CaneModel {
  bool enabled = false;
  double length_m = 1.2;              ///< reach of the tip from the body's centre
  double sweep_half_angle_rad = 0.45; ///< the tip's arc each side of the walking line
  double detect_height_m = 0.3;       ///< the cane finds what reaches below this height
  double tip_radius_m = 0.03;
};

/// Throws ConfigError naming the field (user.body.*, user.cane.*) when a value is out of range.
void validate(const BodyModel& body);
void validate(const CaneModel& cane);

struct Contact {
  double t_s = 0;
  BodyPart part = BodyPart::kLegs;  ///< the part that touched first (the highest, if several at once)
  bool moving = false;              ///< a moving person or vehicle (primitive: its index in the moving world)
  std::uint32_t primitive = 0;
  SemanticClass semantic = SemanticClass::kUnlabeled;
  double height_m = 0;              ///< above the ground: the middle of the touched part's overlap with the obstacle
  Vec2 where_W = Vec2::Zero();      ///< the body's (or the cane tip's) position at the touch
};

/// What the cane feels now: the nearest obstacle in its sector.
struct CaneTouch {
  double bearing_rad = 0;   ///< relative to the walking heading, positive to the left
  double distance_m = 0;    ///< from the body's centre
  bool moving = false;
  std::uint32_t primitive = 0;
};

class ContactMonitor {
 public:
  /// `statics`: the scenario's static world (kept by reference: it must outlive the monitor).
  ContactMonitor(const World& statics, double ground_z_m, const BodyModel& body, const CaneModel& cane);

  /// Contacts that begin at time t for the body at `position` walking along `heading_rad`;
  /// `moving`: the people and vehicles at t (moving_world), may be empty.
  std::vector<Contact> update(double t_s, const Vec2& position, double heading_rad, const World& moving);

  /// A static primitive the body would walk into going `distance_m` from `position` along
  /// `heading_rad` (checked every 5 cm), other than those it touches already; none when the way is
  /// clear. For guidance that points into an obstacle.
  std::optional<std::uint32_t> blocked_along(const Vec2& position, double heading_rad, double distance_m) const;

  /// Whether a step of the body from `from` to `to` runs into a static primitive: the body touches
  /// one at `to` and is nearer to it than at `from` (one who stands against a wall may step away).
  /// Returns the obstacle as felt: its bearing relative to `heading_rad` and its distance. People
  /// and vehicles do not stop the body (they are counted as contacts and move on).
  std::optional<CaneTouch> bump(const Vec2& from, const Vec2& to, double heading_rad) const;

  /// The cane's touch found by the last update, if any.
  const std::optional<CaneTouch>& cane_touch() const { return cane_touch_; }

 private:
  struct Hit {
    BodyPart part;
    bool moving;
    std::uint32_t primitive;
  };
  /// Whether the body at p touches static primitive i.
  bool body_touches(std::uint32_t i, const Vec2& p) const;
  void check_world(const World& world, bool moving, const Vec2& position, double heading_rad, std::vector<Hit>& hits);

  const World* statics_;
  std::vector<AxisAlignedBox> static_bounds_;
  double ground_z_;
  BodyModel body_;
  CaneModel cane_;
  using Key = std::tuple<bool, bool, std::uint32_t>;  ///< (by the cane, moving, primitive)
  std::set<Key> touching_;
  std::optional<CaneTouch> cane_touch_;
};

}  // namespace navaid::simulation
