// The semantic voxel map: ray casting, class votes, clearing of what moved away, the scrolling
// window, .ot round trips and exports.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>

#include <octomap/AbstractOcTree.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/semantic_map.hpp"
#include "navaid/mapping/semantic_octree.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

using C = SemanticClass;

/// A square patch of points in the plane x = x0 (|y|, |z - zc| <= half), one per `step`.
void add_wall(SemanticPointCloud& cloud, double x0, double zc, double half, double step, C semantic, float p) {
  for (double y = -half; y <= half + 1e-9; y += step)
    for (double z = zc - half; z <= zc + half + 1e-9; z += step)
      cloud.points.push_back({Eigen::Vector3f(static_cast<float>(x0), static_cast<float>(y), static_cast<float>(z)),
                              {semantic, p}});
}

SemanticPointCloud wall_cloud(double x0, C semantic = C::kWall, float p = 0.8f) {
  SemanticPointCloud cloud;
  cloud.origin_W = Vec3(0, 0, 1);
  cloud.labelled = true;
  add_wall(cloud, x0, 1.0, 0.5, 0.02, semantic, p);
  return cloud;
}

SemanticMapConfig small_config(FusionPolicy policy = FusionPolicy::kMax) {
  SemanticMapConfig c;
  c.resolution_m = 0.1;
  c.fusion = policy;
  return c;
}

TEST(SemanticMap, RaysMarkFreeSpaceAndHitsOccupied) {
  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  const InsertStats s = map.insert(wall_cloud(3.05));
  EXPECT_EQ(s.points, 51u * 51u);
  EXPECT_EQ(s.outside_window, 0u);
  // 51 x 51 points 2 cm apart on a 1 m square: 10 x 10 voxels plus the edge row/column in the next.
  EXPECT_GE(s.occupied_voxels, 100u);
  EXPECT_LE(s.occupied_voxels, 121u);
  const auto wall = map.voxel_at(Vec3(3.05, 0.05, 1.05));
  ASSERT_TRUE(wall);
  EXPECT_GT(wall->occupancy, 0.5);
  EXPECT_EQ(wall->semantic, C::kWall);
  EXPECT_FLOAT_EQ(static_cast<float>(wall->class_probability), 0.8f);
  const auto between = map.voxel_at(Vec3(1.5, 0.0, 1.0));
  ASSERT_TRUE(between);
  EXPECT_LT(between->occupancy, 0.5);
  EXPECT_FALSE(map.voxel_at(Vec3(-2.0, 0.0, 1.0)));  // behind the camera: never seen
  for (const auto& v : map.occupied_voxels()) EXPECT_NEAR(v.center_W.x(), 3.05, 0.051);
}

TEST(SemanticMap, EveryPointVotesInOrder) {
  // Two points in the same voxel, car then pole: one ray, two votes (max fusion's rule).
  SemanticMap map(small_config());
  map.set_window_center(Vec3::Zero());
  SemanticPointCloud cloud;
  cloud.labelled = true;
  cloud.points.push_back({Eigen::Vector3f(2.01f, 0.01f, 0.01f), {C::kCar, 0.6f}});
  cloud.points.push_back({Eigen::Vector3f(2.02f, 0.02f, 0.02f), {C::kPole, 0.9f}});
  EXPECT_EQ(map.insert(cloud).occupied_voxels, 1u);
  const auto v = map.voxel_at(Vec3(2.05, 0.05, 0.05));
  ASSERT_TRUE(v);
  EXPECT_EQ(v->semantic, C::kPole);
  EXPECT_NEAR(v->class_probability, 0.81, 1e-6);
}

TEST(SemanticMap, UnlabelledFramesMapGeometryOnly) {
  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  SemanticPointCloud cloud = wall_cloud(2.05, C::kUnlabeled, 0.0f);
  cloud.labelled = false;
  map.insert(cloud);
  const auto v = map.voxel_at(Vec3(2.05, 0.05, 1.05));
  ASSERT_TRUE(v);
  EXPECT_GT(v->occupancy, 0.5);
  EXPECT_EQ(v->semantic, C::kUnlabeled);
}

TEST(SemanticMap, APersonWhoLeavesIsClearedAfterTheExpectedNumberOfFrames) {
  // A person 2 m ahead in front of a wall at 4 m, seen for 30 frames (clamped occupied), then gone:
  // the rays to the wall pass through the person's voxels. From the clamp log-odds(0.97) = 3.48,
  // each miss adds log-odds(0.4) = -0.405: ceil(3.48 / 0.405) = 9 frames to fall to p <= 0.5.
  SemanticMapConfig c = small_config();
  SemanticMap map(c);
  map.set_window_center(Vec3(0, 0, 1));
  SemanticPointCloud with_person;
  with_person.origin_W = Vec3(0, 0, 1);
  with_person.labelled = true;
  add_wall(with_person, 2.05, 1.0, 0.25, 0.02, C::kPerson, 0.9f);
  for (int i = 0; i < 30; ++i) map.insert(with_person);
  const Vec3 person(2.05, 0.05, 1.05);
  ASSERT_GT(map.voxel_at(person)->occupancy, 0.96);
  const SemanticPointCloud empty_street = wall_cloud(4.05);
  const int expected = static_cast<int>(std::ceil(octomap::logodds(c.clamp_max) / -octomap::logodds(c.prob_miss)));
  int frames = 0;
  while (map.voxel_at(person)->occupancy > c.occupancy_threshold && frames < 100) {
    map.insert(empty_street);
    ++frames;
  }
  EXPECT_EQ(expected, 9);
  EXPECT_EQ(frames, expected);
}

TEST(SemanticMap, WindowDropsFarPointsAndPrunesWhatIsLeftBehind) {
  SemanticMapConfig c = small_config();
  c.window_size_m = 10.0;
  SemanticMap map(c);
  map.set_window_center(Vec3(0, 0, 1));
  EXPECT_GT(map.insert(wall_cloud(8.05)).outside_window, 0u);  // x = 8 is outside the 5 m half-width
  EXPECT_EQ(map.leaf_count(), 0u);
  map.insert(wall_cloud(3.05));
  const std::size_t leaves = map.leaf_count();
  EXPECT_GT(leaves, 0u);
  ASSERT_TRUE(map.voxel_at(Vec3(3.05, 0.05, 1.05)));
  map.set_window_center(Vec3(20, 0, 1));  // walked 20 m on: the old wall is far behind
  EXPECT_FALSE(map.voxel_at(Vec3(3.05, 0.05, 1.05)));
  EXPECT_EQ(map.leaf_count(), 0u);
  EXPECT_TRUE(map.occupied_voxels().empty());
}

TEST(SemanticMap, MemoryStaysBoundedOnALongWalk) {
  SemanticMap map(small_config());
  std::size_t peak_after_warmup = 0, first_peak = 0;
  for (int step = 0; step < 200; ++step) {
    const double x = 0.5 * step;  // 100 m walk along x, a wall 3 m ahead each time
    map.set_window_center(Vec3(x, 0, 1));
    SemanticPointCloud cloud = wall_cloud(x + 3.05);
    cloud.origin_W = Vec3(x, 0, 1);
    map.insert(cloud);
    if (step == 40) first_peak = map.leaf_count();
    if (step > 40) peak_after_warmup = std::max(peak_after_warmup, map.leaf_count());
  }
  EXPECT_GT(first_peak, 0u);
  EXPECT_LT(peak_after_warmup, first_peak * 3 / 2);  // no growth with distance walked
}

class SemanticMapFiles : public ::testing::TestWithParam<FusionPolicy> {};

TEST_P(SemanticMapFiles, OtRoundTripKeepsOccupancyAndClasses) {
  navaid::testing::ScratchDir dir("semantic-map-ot");
  SemanticMap map(small_config(GetParam()));
  map.set_window_center(Vec3(0, 0, 1));
  map.insert(wall_cloud(3.05, C::kCar, 0.7f));
  map.insert(wall_cloud(2.55, C::kBench, 0.6f));
  map.save(dir / "map.ot");
  const SemanticMap back = SemanticMap::load(dir / "map.ot");
  EXPECT_EQ(back.config().fusion, GetParam());
  EXPECT_DOUBLE_EQ(back.config().resolution_m, 0.1);
  // The window is not stored: put the reloaded map's window where the original's is.
  SemanticMap reloaded = SemanticMap::load(dir / "map.ot");
  reloaded.set_window_center(Vec3(0, 0, 1));
  const MapVoxels a = map.occupied_voxels(), b = reloaded.occupied_voxels();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_FALSE(a.empty());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].center_W, b[i].center_W);
    EXPECT_EQ(a[i].semantic, b[i].semantic);
    EXPECT_FLOAT_EQ(static_cast<float>(a[i].class_probability), static_cast<float>(b[i].class_probability));
    EXPECT_NEAR(a[i].occupancy, b[i].occupancy, 1e-6);
  }
}

TEST(SemanticMapFiles, AWindowBeyondTheAddressableRangeReadsTheWholeMap) {
  // `navaid plan --map RUN/map` reads a saved map "everywhere" (a 1e6 m window): the box is
  // clipped to the tree, where OctoMap's box iterator would wrap its keys and crash.
  navaid::testing::ScratchDir dir("semantic-map-everywhere");
  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  map.insert(wall_cloud(3.05));
  map.save(dir / "map.ot");
  SemanticMapConfig whole = small_config();
  whole.window_size_m = 1e6;
  whole.window_below_m = whole.window_above_m = 1e6;
  const SemanticMap back = SemanticMap::load(dir / "map.ot", whole);
  EXPECT_EQ(back.occupied_voxels().size(), map.occupied_voxels().size());
  const SemanticMap empty(whole);
  EXPECT_TRUE(empty.occupied_voxels().empty());
}

INSTANTIATE_TEST_SUITE_P(BothPolicies, SemanticMapFiles, ::testing::Values(FusionPolicy::kMax, FusionPolicy::kBayes));

TEST(SemanticMapFiles, CorruptTruncatedAndForeignFilesAreClearErrors) {
  navaid::testing::ScratchDir dir("semantic-map-bad");
  EXPECT_NE(navaid::testing::error_message<IoError>([&] { SemanticMap::load(dir / "missing.ot"); }).find("missing.ot"),
            std::string::npos);
  navaid::testing::write_text(dir / "garbage.ot", "this is not an octree\n");
  EXPECT_NE(navaid::testing::error_message<IoError>([&] { SemanticMap::load(dir / "garbage.ot"); }).find("garbage.ot"),
            std::string::npos);

  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  map.insert(wall_cloud(3.05));
  map.save(dir / "whole.ot");
  const std::string whole = navaid::testing::read_text(dir / "whole.ot");
  navaid::testing::write_text(dir / "cut.ot", whole.substr(0, whole.size() * 2 / 3));
  EXPECT_NE(navaid::testing::error_message<IoError>([&] { SemanticMap::load(dir / "cut.ot"); }).find("truncated"),
            std::string::npos);

  octomap::OcTree plain(0.1);
  plain.updateNode(octomap::point3d(1, 1, 1), true);
  plain.write((dir / "plain.ot").string());
  EXPECT_NE(navaid::testing::error_message<IoError>([&] { SemanticMap::load(dir / "plain.ot"); }).find("'OcTree'"),
            std::string::npos);
}

TEST(SemanticMapFiles, ColorOcTreeExportCarriesClassColours) {
  navaid::testing::ScratchDir dir("semantic-map-color");
  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  map.insert(wall_cloud(3.05, C::kVegetation, 0.8f));
  map.write_color_octree(dir / "map-color.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read((dir / "map-color.ot").string()));
  ASSERT_TRUE(tree);
  auto* color = dynamic_cast<octomap::ColorOcTree*>(tree.get());
  ASSERT_NE(color, nullptr);
  const octomap::ColorOcTreeNode* n = color->search(3.05, 0.05, 1.05);
  ASSERT_NE(n, nullptr);
  EXPECT_TRUE(color->isNodeOccupied(n));
  const auto& rgb = semantic_class_info(C::kVegetation).rgb;
  EXPECT_EQ(n->getColor(), octomap::ColorOcTreeNode::Color(rgb[0], rgb[1], rgb[2]));
}

TEST(SemanticMapFiles, AnEmptyMapWritesAnEmptyColorOcTree) {
  // A device that never maps (w-roma) still writes its map folder: OctoMap 1.9 crashed on the
  // inner-node update of an empty tree.
  navaid::testing::ScratchDir dir("semantic-map-color-empty");
  SemanticMap map(small_config());
  map.write_color_octree(dir / "map-color.ot");
  std::unique_ptr<octomap::AbstractOcTree> tree(octomap::AbstractOcTree::read((dir / "map-color.ot").string()));
  ASSERT_TRUE(tree);
  EXPECT_EQ(tree->size(), 0u);
}

TEST(SemanticMapFiles, PlyListsTheOccupiedVoxels) {
  navaid::testing::ScratchDir dir("semantic-map-ply");
  SemanticMap map(small_config());
  map.set_window_center(Vec3(0, 0, 1));
  map.insert(wall_cloud(3.05));
  map.write_ply(dir / "map.ply");
  const std::string ply = navaid::testing::read_text(dir / "map.ply");
  const std::size_t n = map.occupied_voxels().size();
  EXPECT_NE(ply.find("element vertex " + std::to_string(n) + "\n"), std::string::npos);
  const std::size_t body = ply.find("end_header\n") + 11;
  EXPECT_EQ(static_cast<std::size_t>(std::count(ply.begin() + static_cast<long>(body), ply.end(), '\n')), n);
}

TEST(SemanticMap, ConfigKeys) {
  const Config c = Config::parse("mapping: {map: {resolution_m: 0.05, fusion: bayes, window_size_m: 12}}");
  const auto m = read_semantic_map_config(c);
  EXPECT_DOUBLE_EQ(m.resolution_m, 0.05);
  EXPECT_EQ(m.fusion, FusionPolicy::kBayes);
  EXPECT_DOUBLE_EQ(m.window_size_m, 12.0);
  EXPECT_THROW(read_semantic_map_config(Config::parse("mapping: {map: {fusion: mean}}")), ConfigError);
  EXPECT_THROW(read_semantic_map_config(Config::parse("mapping: {map: {prob_hit: 0.3}}")), ConfigError);
}

}  // namespace
}  // namespace navaid::mapping
