#pragma once
// Ground truth of tagged target objects (hand guidance, W-ROMA Sec. IV): `targets.csv` of a
// simulated recording (docs/recording-format.md), one row per object:
//   name,class,family,tag_id,tag_size_m,cx,cy,cz,hx,hy,hz,tx,ty,tz,qw,qx,qy,qz
// centre c and half extents h of the object's box, and the tag frame T_W_tag (origin at the tag's
// centre on the face, x right and y down across the printed face, z into the face; the pose
// reported by an AprilTag detector, in W), all in metres.
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/semantic_classes.hpp"

namespace navaid::io {

struct TargetGroundTruth {
  std::string name;  ///< no commas, not empty
  SemanticClass semantic = SemanticClass::kTargetObject;
  std::string tag_family = "36h11";
  int tag_id = 0;
  double tag_size_m = 0.0;  ///< side of the black square
  Vec3 center_W = Vec3::Zero();
  Vec3 half_extents = Vec3::Zero();
  SE3 T_W_tag;
};

inline constexpr const char* kTargetsCsv = "targets.csv";

/// Writes the file (IoError when it cannot be written, std::invalid_argument on a name with a
/// comma or a newline, a negative tag id or a non-finite number).
void write_targets_csv(const std::filesystem::path& path, const std::vector<TargetGroundTruth>& targets);

/// Reads the file; IoError naming file:line on a wrong header, field count, class name, number,
/// a negative tag id, a non-positive tag size or a quaternion that is not unit within 1e-3.
std::vector<TargetGroundTruth> read_targets_csv(const std::filesystem::path& path);

}  // namespace navaid::io
