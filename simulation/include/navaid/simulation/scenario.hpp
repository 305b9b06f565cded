#pragma once
// The scenario library: named, documented worlds with a walking path, moving people/vehicles and a
// geodetic origin, modelled on the set-ups of the seed papers (docs/scenarios.md). Names are
// stable; generation is deterministic from a seed (0 = the scenario's documented default seed).
//
// Frames: W has x east, y north, z up (so ENU at `origin` equals W). Walked surfaces are at
// z = ground_z_m; roads and crossings may lie a low step below.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "navaid/core/calibration.hpp"
#include "navaid/simulation/ray_caster.hpp"
#include "navaid/simulation/world.hpp"

namespace navaid::simulation {

enum class MovingKind { kPerson, kCar };

/// A person or vehicle moving at constant speed along a polyline (piecewise linear, exact).
struct MovingObject {
  MovingKind kind = MovingKind::kPerson;
  std::vector<Vec2> path;     ///< >= 1 point in W (one point: standing still)
  double speed_mps = 1.2;     ///< > 0
  double start_s = 0.0;       ///< waits at path.front() until this time
  bool loop = false;          ///< true: closed loop (last point back to the first), forever; false: stops at the end
  double radius_m = 0.25;     ///< person: body radius; car: half width (length = 2.4 x width)
  double height_m = 1.7;      ///< overall height
};

/// Position at time t [s]; deterministic, continuous in t. Throws navaid::Error on an empty path
/// or non-positive speed.
Vec2 moving_position(const MovingObject& m, double t_s);
/// Unit direction of motion at t (the current segment; the first segment before the start and
/// the last one after the end).
Vec2 moving_heading(const MovingObject& m, double t_s);
/// Primitives of the moving objects at time t: a person is a body cylinder plus a head ellipsoid
/// (class person), a car a body box plus a cabin box (class car), oriented along the motion.
World moving_world(const std::vector<MovingObject>& objects, double t_s);

enum class ScenarioKind { kWalk, kPlannerMap };

/// An object the hand-guidance user reaches for (W-ROMA Sec. IV), with an AprilTag printed on one
/// face; its primitives carry the target-object class. Ground truth of `navaid simulate`
/// (targets.csv, docs/recording-format.md).
struct TargetObject {
  std::string name;                  ///< e.g. "box-on-desk"
  SemanticClass semantic = SemanticClass::kTargetObject;
  Vec3 center_W = Vec3::Zero();      ///< centre of the object [m]
  Vec3 half_extents = Vec3::Zero();  ///< of the object's box, along its axes [m]
  std::string tag_family = "36h11";
  int tag_id = 0;
  double tag_size_m = 0.0;           ///< side of the tag's black square [m]
  /// Tag frame as AprilTag detectors report it (apriltag_image.hpp): origin at the tag's centre on
  /// the face, x right and y down across the printed face, z into the face.
  SE3 T_W_tag;
  std::vector<std::uint32_t> primitives;  ///< the object's and the tag's primitives
};

struct Scenario {
  std::string name, description;
  ScenarioKind kind = ScenarioKind::kWalk;
  std::uint64_t seed = 0;                ///< the seed actually used
  World world;                           ///< static geometry
  std::vector<Vec2> path;                ///< walking waypoints in W (>= 2)
  double ground_z_m = 0.0;               ///< z of the walked surface
  GeodeticOrigin origin;                 ///< geodetic origin of W (ENU = W)
  std::vector<MovingObject> moving;      ///< people and vehicles (empty when switched off)
  AxisAlignedBox extent;                 ///< documented size of the scene (x, y and height)
  std::string default_mount;             ///< "head", "cane" or "hand"
  /// Primitives the path deliberately meets (obstacles the user must avoid, e.g. low branches
  /// over the sidewalk): exempt from the path clearance rule.
  std::vector<std::uint32_t> deliberate_obstacles;
  /// Obstacles placed beside the path for the user to avoid (the path keeps its clearance from
  /// them): the corridor's stations, the obstacle course's waist-high hanging obstacle.
  std::vector<std::uint32_t> placed_obstacles;
  /// Tagged target objects for hand guidance (the lab walks have one).
  std::vector<TargetObject> targets;
  /// Read by the builders: whether to place the target objects (ScenarioOptions::targets).
  bool place_targets = true;
  /// Read by the builders: ScenarioOptions::random_layout.
  bool random_layout = false;
};

struct ScenarioOptions {
  std::uint64_t seed = 0;   ///< 0 = the scenario's documented default seed
  bool people = true;       ///< moving people
  bool vehicles = true;     ///< moving vehicles
  /// Target objects for hand guidance (the lab walks' tagged box). Off gives the world as it was
  /// before the box (studies that must keep their data, e.g. the estimator tests' lab walks).
  bool targets = true;
  /// Randomize the obstacle layout by the seed (simulation.layout=random) where a scenario has
  /// a random family (corridor, obstacle-course); elsewhere the seed's usual jitter.
  bool random_layout = false;
};

/// All scenario names, in documentation order.
std::vector<std::string> scenario_names();
/// The documented default seed of a scenario; ConfigError (key "scenario") when unknown.
std::uint64_t default_scenario_seed(std::string_view name);
/// Builds a scenario. ConfigError (key "scenario") listing the known names when `name` is unknown.
Scenario make_scenario(std::string_view name, const ScenarioOptions& options = {});

/// Static world plus the moving objects at time t.
World world_at(const Scenario& scenario, double t_s);

/// Length of a polyline [m].
double polyline_length(const std::vector<Vec2>& path);

/// Body heights checked by the walkability rule: between ankle and above-head height.
struct ClearanceBand {
  double z_min_m = 0.2;   ///< curbs and low steps (<= 0.15 m) are stepped over
  double z_max_m = 2.0;   ///< head of a tall walker plus margin
};

/// Horizontal distance [m] from the vertical segment at p between heights z_lo and z_hi (absolute,
/// in W) to one primitive: 0 when the segment is inside it, infinity when the primitive has nothing
/// between those heights. Exact for upright boxes, cylinders, polygons and ellipsoids; a lower bound
/// otherwise (tilted shapes by their bounding box).
double horizontal_distance(const Shape& shape, const Vec2& p, double z_lo, double z_hi);

/// Smallest horizontal distance [m] from the vertical segment at p (z in the band, relative to
/// ground_z) to any primitive of `world` not listed in `ignore` (0 when inside one). Boxes and
/// ellipsoids are taken exactly when upright (yaw only), conservatively otherwise.
double horizontal_clearance(const World& world, const Vec2& p, double ground_z_m, const ClearanceBand& band = {},
                            const std::vector<std::uint32_t>& ignore = {});
/// Minimum of horizontal_clearance over the polyline sampled every `step_m`.
double path_clearance(const World& world, const std::vector<Vec2>& path, double ground_z_m, double step_m = 0.1,
                      const ClearanceBand& band = {}, const std::vector<std::uint32_t>& ignore = {});

/// Fraction in [0, 1] of sky directions blocked by geometry, seen from p_W: 24 azimuths x
/// elevations 15, 25, 35, 45 deg (the low sky a GNSS receiver loses in a street canyon).
double urban_canyon_factor(const RayCaster& static_world, const Vec3& p_W);

}  // namespace navaid::simulation
