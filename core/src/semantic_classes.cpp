#include "navaid/core/semantic_classes.hpp"

#include <cassert>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid {

namespace {
using C = SemanticClass;
// Colours follow the Mapillary Vistas palette where the class exists there.
constexpr std::array<SemanticClassInfo, kNumSemanticClasses> kClasses{{
    {C::kUnlabeled, "unlabeled", {0, 0, 0}},
    {C::kSidewalk, "sidewalk", {244, 35, 232}},
    {C::kRoad, "road", {128, 64, 128}},
    {C::kCurb, "curb", {196, 196, 196}},
    {C::kCrosswalk, "crosswalk", {200, 128, 128}},
    {C::kTerrain, "terrain", {152, 251, 152}},
    {C::kBuilding, "building", {70, 70, 70}},
    {C::kWall, "wall", {102, 102, 156}},
    {C::kFence, "fence", {190, 153, 153}},
    {C::kPole, "pole", {153, 153, 153}},
    {C::kTrafficSign, "traffic-sign", {220, 220, 0}},
    {C::kTreeTrunk, "tree-trunk", {120, 80, 40}},
    {C::kVegetation, "vegetation", {107, 142, 35}},
    {C::kBench, "bench", {250, 0, 30}},
    {C::kBusStop, "bus-stop", {255, 170, 0}},
    {C::kCar, "car", {0, 0, 142}},
    {C::kBicycle, "bicycle", {119, 11, 32}},
    {C::kPerson, "person", {220, 20, 60}},
    {C::kSky, "sky", {70, 130, 180}},
    {C::kFloor, "floor", {210, 180, 140}},
    {C::kCeiling, "ceiling", {240, 240, 200}},
    {C::kDoor, "door", {0, 160, 160}},
    {C::kChair, "chair", {255, 100, 200}},
    {C::kTable, "table", {160, 60, 255}},
    {C::kTactilePaving, "tactile-paving", {255, 215, 0}},
    {C::kTargetObject, "target-object", {0, 255, 128}},
}};

constexpr bool ids_match_positions() {
  for (std::size_t i = 0; i < kClasses.size(); ++i) {
    if (static_cast<std::size_t>(kClasses[i].id) != i) return false;
  }
  return true;
}
static_assert(ids_match_positions(), "semantic class table must be indexed by id");
}  // namespace

const std::array<SemanticClassInfo, kNumSemanticClasses>& semantic_classes() { return kClasses; }

const SemanticClassInfo& semantic_class_info(SemanticClass c) {
  const auto i = static_cast<std::size_t>(c);
  assert(i < kNumSemanticClasses);
  return kClasses[i];
}

std::string_view semantic_class_name(SemanticClass c) { return semantic_class_info(c).name; }

SemanticClass semantic_class_from_name(std::string_view name) {
  for (const auto& info : kClasses) {
    if (info.name == name) return info.id;
  }
  std::string known;
  for (const auto& info : kClasses) {
    if (!known.empty()) known += ", ";
    known += info.name;
  }
  throw ConfigError("", "semantic_class", "unknown semantic class '" + std::string(name) + "'; known: " + known);
}

bool is_valid_semantic_id(std::uint8_t id) { return id < kNumSemanticClasses; }

}  // namespace navaid
