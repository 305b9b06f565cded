#pragma once
// The one semantic label set of navaid (docs/semantic-classes.md), shared by the simulator and the
// semantic map; modelled on the Mapillary Vistas classes that eLabrador's segmentation uses, plus
// the indoor classes of the cane scenes.
// Ids are stable uint8 values written into label images and recordings: never renumber, only
// append. Id 0 is "unlabeled".
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace navaid {

enum class SemanticClass : std::uint8_t {
  kUnlabeled = 0,
  kSidewalk = 1,
  kRoad = 2,
  kCurb = 3,
  kCrosswalk = 4,
  kTerrain = 5,
  kBuilding = 6,
  kWall = 7,
  kFence = 8,
  kPole = 9,
  kTrafficSign = 10,
  kTreeTrunk = 11,
  kVegetation = 12,
  kBench = 13,
  kBusStop = 14,
  kCar = 15,
  kBicycle = 16,
  kPerson = 17,
  kSky = 18,
  kFloor = 19,
  kCeiling = 20,
  kDoor = 21,
  kChair = 22,
  kTable = 23,
  kTactilePaving = 24,
  kTargetObject = 25,  ///< the object the hand-guidance user reaches for (W-ROMA Sec. IV)
};

/// Number of classes; ids are 0 .. kNumSemanticClasses - 1 without gaps.
inline constexpr std::size_t kNumSemanticClasses = 26;

struct SemanticClassInfo {
  SemanticClass id;
  std::string_view name;           ///< lower-case, hyphenated ("traffic-sign"), as in configs
  std::array<std::uint8_t, 3> rgb;  ///< display colour
};

/// All classes, indexed by id.
const std::array<SemanticClassInfo, kNumSemanticClasses>& semantic_classes();

/// Info of a class; the id must be valid (asserted).
const SemanticClassInfo& semantic_class_info(SemanticClass c);
std::string_view semantic_class_name(SemanticClass c);

/// Class by name (exact, lower case, e.g. "tree-trunk"); throws ConfigError (key "semantic_class")
/// listing the known names when the name is unknown.
SemanticClass semantic_class_from_name(std::string_view name);

/// True when id < kNumSemanticClasses.
bool is_valid_semantic_id(std::uint8_t id);

}  // namespace navaid
