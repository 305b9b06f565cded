// The 3D ESDF over navaid's own semantic tree (Esdf3d is templated over the OctoMap tree type):
// distances against brute force over the occupied voxels.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "navaid/mapping/esdf_3d.hpp"
#include "navaid/mapping/semantic_octree.hpp"

namespace navaid::mapping {
namespace {

TEST(Esdf3dSemanticTree, DistancesEqualBruteForceOnASemanticOcTree) {
  MaxFusionOcTree tree(0.1);
  std::vector<Vec3> occupied;
  // A wall at x = 2 (a 1 m x 1 m patch) and a hanging box at head height, with class votes.
  for (double y = -0.45; y <= 0.45 + 1e-9; y += 0.1)
    for (double z = 0.05; z <= 0.95 + 1e-9; z += 0.1) occupied.emplace_back(2.05, y, z);
  for (double x = 1.05; x <= 1.25 + 1e-9; x += 0.1) occupied.emplace_back(x, 0.05, 1.65);
  for (const auto& p : occupied) {
    auto* node = tree.updateNode(octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                                  static_cast<float>(p.z())),
                                 true);
    tree.fuse(node, {SemanticClass::kWall, 0.8f});
  }
  Esdf3dConfig config;
  config.max_distance_m = 3.0;
  Esdf3d<MaxFusionOcTree> esdf(tree, Vec3(-1, -2, -1), Vec3(4, 2, 3), config);
  for (const Vec3& q : {Vec3(1.05, 0.05, 0.55), Vec3(0.55, 0.35, 1.25), Vec3(1.15, 0.05, 1.35), Vec3(2.05, 0.05, 0.45)}) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& p : occupied) best = std::min(best, (p - q).norm());
    const auto d = esdf.voxel_distance(q);
    ASSERT_TRUE(d.has_value());
    EXPECT_NEAR(*d, best, 1e-4) << q.transpose();
  }
}

}  // namespace
}  // namespace navaid::mapping
