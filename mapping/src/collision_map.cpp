#include "navaid/mapping/collision_map.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/config_schema.hpp"

namespace navaid::mapping {

namespace {

// navaid's Table II. eLabrador's own values are not recoverable from the seed text (only the
// table's caption survived), so these are our choice, class by class: 0 for surfaces a blind
// pedestrian walks on, 1 for solid things one must not walk into, values in between for surfaces
// that are walkable but to be avoided. A voxel only counts inside the walking band p(m) = 1, so a
// class that is harmless above the head (ceiling) still blocks when it hangs into the band.
SemanticCollisionTable make_default_table() {
  SemanticCollisionTable t{};
  const auto set = [&t](SemanticClass c, double p) { t[static_cast<std::size_t>(c)] = p; };
  set(SemanticClass::kUnlabeled, 1.0);      // geometry only: an occupied voxel in the band is an obstacle
  set(SemanticClass::kSidewalk, 0.0);       // the walking surface
  set(SemanticClass::kRoad, 0.8);           // walkable but traffic: costly, yet crossable when needed
  set(SemanticClass::kCurb, 0.5);           // a trip edge; the undulation map marks its step
  set(SemanticClass::kCrosswalk, 0.0);      // where the road is meant to be crossed
  set(SemanticClass::kTerrain, 0.3);        // grass, gravel: walkable, uneven, the cane reads it less well
  set(SemanticClass::kBuilding, 1.0);       // solid
  set(SemanticClass::kWall, 1.0);           // solid
  set(SemanticClass::kFence, 1.0);          // solid
  set(SemanticClass::kPole, 1.0);           // thin, solid, the classic white-cane miss
  set(SemanticClass::kTrafficSign, 1.0);    // often at head height: solid
  set(SemanticClass::kTreeTrunk, 1.0);      // solid
  set(SemanticClass::kVegetation, 0.8);     // hedges and branches: soft but not passable
  set(SemanticClass::kBench, 1.0);          // solid, low: a knee hit
  set(SemanticClass::kBusStop, 1.0);        // shelter walls and posts
  set(SemanticClass::kCar, 1.0);            // parked or moving: never walk into
  set(SemanticClass::kBicycle, 1.0);        // solid, often parked on the sidewalk
  set(SemanticClass::kPerson, 1.0);         // must not be walked into
  set(SemanticClass::kSky, 0.0);            // a sky voxel is a depth artefact, not matter
  set(SemanticClass::kFloor, 0.0);          // the indoor walking surface
  set(SemanticClass::kCeiling, 1.0);        // harmless above the band; inside it, a low beam
  set(SemanticClass::kDoor, 1.0);           // door voxels are the leaf itself; an open doorway has none
  set(SemanticClass::kChair, 1.0);          // solid
  set(SemanticClass::kTable, 1.0);          // solid, its top at hip height
  set(SemanticClass::kTactilePaving, 0.0);  // the guidance surface for blind pedestrians
  set(SemanticClass::kTargetObject, 1.0);   // the object to be grasped: solid, usually on a table
  return t;
}

constexpr const char* kTableKey = "mapping.collision.semantic_probability";

}  // namespace

const SemanticCollisionTable& default_semantic_collision_table() {
  static const SemanticCollisionTable table = make_default_table();
  return table;
}

namespace {
const ConfigKey<double> kCollisionMapOccupiedThreshold{"mapping.collision.occupied_threshold", CollisionConfig{}.occupied_threshold,
                                           {0.01, 1.0}, "voxels with occupancy at or above this enter eq. (9)"};
const ConfigKey<double> kMinRelativeHeight{"mapping.collision.min_relative_height_m",
                                           CollisionConfig{}.min_relative_height_m, {-10.0, 10.0},
                                           "p(m) = 1 from this height relative to the camera [m] (<= max)"};
const ConfigKey<double> kMaxRelativeHeight{"mapping.collision.max_relative_height_m",
                                           CollisionConfig{}.max_relative_height_m, {-10.0, 10.0},
                                           "p(m) = 1 up to this height relative to the camera [m]"};
const ConfigMapKey kSemanticTable{kTableKey, "probability in [0, 1] per semantic class name",
                                  "collision probability of a class (classes not given keep their default)"};
}  // namespace

ConfigSchema collision_config_schema() {
  return ConfigSchema().add(kCollisionMapOccupiedThreshold).add(kMinRelativeHeight).add(kMaxRelativeHeight).add(kSemanticTable);
}

CollisionConfig read_collision_config(const Config& config) {
  CollisionConfig c;
  c.occupied_threshold = get(config, kCollisionMapOccupiedThreshold);
  c.min_relative_height_m = get(config, kMinRelativeHeight);
  c.max_relative_height_m = get(config, kMaxRelativeHeight);
  if (c.min_relative_height_m > c.max_relative_height_m) {
    const std::string key = "mapping.collision.min_relative_height_m";
    throw ConfigError(config.origin(key), key,
                      "must not exceed mapping.collision.max_relative_height_m (" +
                          std::to_string(c.max_relative_height_m) + ")");
  }
  for (const std::string& name : config.child_keys(kTableKey)) {
    const std::string key = std::string(kTableKey) + "." + name;
    const SemanticClassInfo* info = nullptr;
    std::string known;
    for (const SemanticClassInfo& k : semantic_classes()) {
      if (k.name == name) info = &k;
      known += (known.empty() ? "" : ", ") + std::string(k.name);
    }
    if (info == nullptr) throw ConfigError(config.origin(key), key, "unknown semantic class '" + name + "'; known: " + known);
    c.semantic_probability[static_cast<std::size_t>(info->id)] = config.get_double(key, {0.0, 1.0});
  }
  return c;
}

double geometric_collision_probability(double relative_height_m, const CollisionConfig& config) {
  return relative_height_m >= config.min_relative_height_m && relative_height_m <= config.max_relative_height_m
             ? 1.0
             : 0.0;
}

CollisionMap::CollisionMap(const GridGeometry& geometry)
    : GridLayer<float>(geometry, std::numeric_limits<float>::quiet_NaN()) {}

bool CollisionMap::is_known(float p) { return !std::isnan(p); }

CollisionMap build_collision_map(const MapVoxels& voxels, const GridGeometry& geometry, double camera_height_W,
                                 const CollisionConfig& config) {
  // Per cell: sum_h p(g,h) and sum_h p(s) p(m) p(g,h), in double (a pillar can hold many voxels).
  std::vector<double> weight(geometry.num_cells(), 0.0);
  std::vector<double> collision(geometry.num_cells(), 0.0);
  for (const MapVoxel& v : voxels) {
    if (v.occupancy < config.occupied_threshold) continue;
    const double ps = config.semantic_probability[static_cast<std::size_t>(v.semantic)];
    const double pm = geometric_collision_probability(v.center_W.z() - camera_height_W, config);
    for_each_footprint_cell(geometry, v.center_W, v.size_m, [&](const Cell2& c) {
      const std::size_t i = geometry.index(c);
      weight[i] += v.occupancy;
      collision[i] += ps * pm * v.occupancy;
    });
  }
  CollisionMap map(geometry);
  for (int y = 0; y < geometry.height(); ++y) {
    for (int x = 0; x < geometry.width(); ++x) {
      const std::size_t i = geometry.index(Cell2(x, y));
      if (weight[i] > 0.0) map.at(x, y) = static_cast<float>(collision[i] / weight[i]);
    }
  }
  return map;
}

}  // namespace navaid::mapping
