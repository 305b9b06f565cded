// The 2D layers and both distance fields on a real map: OctoMap's geb079 (a corridor of building
// 079, University of Freiburg, 3D laser, 0.08 m; ../shared/data/octomap-geb079). The corridor runs
// along x, its walls' faces near y = -1.4 and y = +1.2, its floor's voxels at z = -0.04. Geometry
// only (no labels): every voxel is kUnlabeled, so the walking band starts above the floor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <octomap/OcTree.h>
#include <random>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/mapping/esdf_3d.hpp"
#include "navaid/mapping/map_png.hpp"
#include "navaid/mapping/octomap_voxels.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

constexpr double kCameraHeight = 1.5;  // an eye-level camera over the floor (z = 0)
const Vec2 kCenter(5.0, -0.1);         // on the corridor's centre line

std::unique_ptr<octomap::OcTree> load_geb079() {
  auto tree = std::make_unique<octomap::OcTree>(0.1);
  const std::string file = (testing::shared_data_dir() / "octomap-geb079" / "geb079.bt").string();
  if (!tree->readBinary(file)) return nullptr;
  return tree;
}

struct Layers {
  GridGeometry geometry;
  HeightMap height;
  UndulationMap undulation;
  CollisionMap collision;
  CostMap cost;
};

Layers build_layers(const octomap::OcTree& tree, double sigma_xy) {
  const GridGeometry g = GridGeometry::around(kCenter, GridConfig{});
  const Vec2 lo = g.origin_W();
  const Vec2 hi = lo + Vec2(g.width(), g.height()) * g.resolution();
  const MapVoxels voxels = octomap_to_voxels(tree, Vec3(lo.x(), lo.y(), -1.0), Vec3(hi.x(), hi.y(), 3.0));
  CollisionConfig collision;
  // Without labels the floor is excluded by the band: from 0.18 m above the floor to eye level.
  collision.min_relative_height_m = -1.32;
  HeightMap h = build_height_map(voxels, g, kCameraHeight, HeightMapConfig{});
  UndulationMap u = build_undulation_map(h, UndulationConfig{});
  CollisionMap c = build_collision_map(voxels, g, kCameraHeight, collision);
  CostMap m = build_cost_map(c, u, sigma_xy, CostMapConfig{});
  return Layers{g, std::move(h), std::move(u), std::move(c), std::move(m)};
}

// Width and height of a PNG from its IHDR chunk.
std::pair<int, int> png_size(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<unsigned char> b(24);
  in.read(reinterpret_cast<char*>(b.data()), 24);
  const auto be32 = [&](int o) { return (b[o] << 24) | (b[o + 1] << 16) | (b[o + 2] << 8) | b[o + 3]; };
  EXPECT_EQ(b[1], 'P');
  return {be32(16), be32(20)};
}

class Geb079Maps : public ::testing::Test {
 protected:
  void SetUp() override {
    NAVAID_REQUIRE_SHARED_DATA();
    tree_ = load_geb079();
    ASSERT_TRUE(tree_) << "cannot read geb079.bt";
    ASSERT_DOUBLE_EQ(tree_->getResolution(), 0.08);
  }
  std::unique_ptr<octomap::OcTree> tree_;
};

TEST_F(Geb079Maps, VoxelsAreTheOccupiedMaxDepthCells) {
  const Vec3 lo(4.0, -1.7, -0.2), hi(5.0, -1.0, 1.0);
  const MapVoxels voxels = octomap_to_voxels(*tree_, lo, hi);
  std::size_t occupied = 0;
  const octomap::OcTreeKey klo = tree_->coordToKey(lo.x(), lo.y(), lo.z());
  const octomap::OcTreeKey khi = tree_->coordToKey(hi.x(), hi.y(), hi.z());
  for (unsigned x = klo[0]; x <= khi[0]; ++x) {
    for (unsigned y = klo[1]; y <= khi[1]; ++y) {
      for (unsigned z = klo[2]; z <= khi[2]; ++z) {
        const octomap::OcTreeNode* n = tree_->search(octomap::OcTreeKey(x, y, z));
        occupied += n != nullptr && tree_->isNodeOccupied(n) ? 1 : 0;
      }
    }
  }
  EXPECT_GT(occupied, 100U);  // a piece of the lower wall
  EXPECT_EQ(voxels.size(), occupied);
  for (const MapVoxel& v : voxels) {
    EXPECT_DOUBLE_EQ(v.size_m, 0.08);
    EXPECT_EQ(v.semantic, SemanticClass::kUnlabeled);
    EXPECT_GE(v.occupancy, 0.5);
  }
}

TEST_F(Geb079Maps, FloorFreeWallsBlockedCorridorWidthPlausible) {
  const Layers L = build_layers(*tree_, 0.0);
  const GridGeometry& g = L.geometry;
  const Cell2 centre = g.cell_of(kCenter);
  // Floor: along the centre line the ground is known, flat, at the floor's voxel height, and free.
  int line = 0, floor_height = 0, free_cells = 0;
  for (int x = 5; x < g.width() - 5; ++x) {
    ++line;
    const float h = L.height.at(x, centre.y());
    floor_height += HeightMap::is_known(h) && std::abs(h - (-0.04F)) < 0.05F ? 1 : 0;
    free_cells += L.cost.at(x, centre.y()) < 0.1F ? 1 : 0;
  }
  EXPECT_GE(floor_height, 0.9 * line) << floor_height << " of " << line;
  EXPECT_GE(free_cells, 0.9 * line) << free_cells << " of " << line;

  // Walls and width, column by column: the nearest obstacle above and below the centre line. Below
  // it is the lower wall (face near y = -1.3); above, the upper wall (y = +1.1 .. 1.3) or the
  // cabinets and benches that stand along it in places (y = +0.2 .. 1.0).
  Esdf2d esdf;
  esdf.update(L.cost);
  std::vector<double> widths;
  int walls_found = 0, columns = 0, growing = 0;
  for (int x = 5; x < g.width() - 5; ++x) {
    ++columns;
    int up = -1, down = -1;
    for (int y = centre.y(); y < g.height() && up < 0; ++y) up = L.cost.is_obstacle(x, y) ? y : -1;
    for (int y = centre.y(); y >= 0 && down < 0; --y) down = L.cost.is_obstacle(x, y) ? y : -1;
    if (up < 0 || down < 0) continue;
    const double y_up = g.cell_center(Cell2(x, up)).y();
    const double y_down = g.cell_center(Cell2(x, down)).y();
    if (!(y_up > 0.2 && y_up < 1.4 && y_down > -1.6 && y_down < -1.0)) continue;
    ++walls_found;
    if (y_up > 0.9) widths.push_back((up - down - 1) * g.resolution());  // free cells, wall to wall
    // On the wall the field is negative; moving off it, it grows cell by cell.
    EXPECT_LT(esdf.field().at(x, down), 0.0F);
    bool monotone = true;
    for (int y = down + 1; y < down + 6; ++y) monotone = monotone && esdf.field().at(x, y) > esdf.field().at(x, y - 1);
    growing += monotone ? 1 : 0;
  }
  EXPECT_GE(walls_found, 0.8 * columns) << walls_found << " of " << columns;
  EXPECT_GE(growing, 0.9 * walls_found) << growing << " of " << walls_found;
  ASSERT_GE(widths.size(), 20U);
  std::nth_element(widths.begin(), widths.begin() + static_cast<long>(widths.size() / 2), widths.end());
  const double median_width = widths[widths.size() / 2];
  EXPECT_GT(median_width, 1.8);  // a university corridor: about 2.5 m between the wall faces,
  EXPECT_LT(median_width, 2.8);  // less the cells the Sobel edge marks beside each wall
  // The centre line keeps more than half a metre to every obstacle, and no more than half the width.
  const double mid = *esdf.distance(kCenter);
  RecordProperty("median_corridor_width_m", std::to_string(median_width));
  RecordProperty("centre_line_esdf_m", std::to_string(mid));
  RecordProperty("columns_with_both_walls", std::to_string(walls_found) + " of " + std::to_string(columns));
  EXPECT_GT(mid, 0.5);
  EXPECT_LT(mid, 0.5 * median_width + g.resolution());
}

TEST_F(Geb079Maps, PositionUncertaintyNarrowsTheCorridor) {
  const Layers sure = build_layers(*tree_, 0.0);
  const Layers unsure = build_layers(*tree_, 0.15);  // r = 0.3 m: 3 cells more on each side of a wall
  int blocked_sure = 0, blocked_unsure = 0;
  for (std::size_t i = 0; i < sure.cost.cells().pixels.size(); ++i) {
    blocked_sure += sure.cost.cells().pixels[i] > 0.9F ? 1 : 0;
    blocked_unsure += unsure.cost.cells().pixels[i] > 0.9F ? 1 : 0;
  }
  EXPECT_GT(blocked_unsure, blocked_sure);
  RecordProperty("blocked_cells_sigma_0", std::to_string(blocked_sure));
  RecordProperty("blocked_cells_sigma_0.15", std::to_string(blocked_unsure));
  Esdf2d a, b;
  a.update(sure.cost);
  b.update(unsure.cost);
  // The blocked ground comes at most r = 0.3 m nearer; on the cell lattice a little less.
  const double loss = *a.distance(kCenter) - *b.distance(kCenter);
  RecordProperty("centre_line_esdf_loss_m", std::to_string(loss));
  EXPECT_LE(loss, 0.3 + 0.02);
  EXPECT_GE(loss, 0.3 - 1.5 * 0.1);
}

TEST_F(Geb079Maps, PngViewsAreWritten) {
  const Layers L = build_layers(*tree_, 0.05);
  Esdf2d esdf;
  esdf.update(L.cost);
  const testing::ScratchDir dir("geb079-png");
  // NAVAID_MAP_PNG_DIR keeps the views for a look (they are not part of the test's verdict).
  const char* keep = std::getenv("NAVAID_MAP_PNG_DIR");
  const std::filesystem::path out = keep != nullptr ? std::filesystem::path(keep) : dir.path();
  write_height_map_png(out / "height.png", L.height);
  write_undulation_map_png(out / "undulation.png", L.undulation);
  write_collision_map_png(out / "collision.png", L.collision);
  write_cost_map_png(out / "cost.png", L.cost);
  write_esdf_png(out / "esdf.png", esdf);
  for (const char* name : {"height.png", "undulation.png", "collision.png", "cost.png", "esdf.png"}) {
    const auto [w, h] = png_size(out / name);
    EXPECT_EQ(w, 400) << name;  // 100 cells at 4 px
    EXPECT_GT(h, 400) << name;  // plus the legend strip
  }
  EXPECT_THROW(write_cost_map_png(dir.path() / "no-such-folder" / "cost.png", L.cost), IoError);
}

TEST_F(Geb079Maps, Esdf3dMatchesBruteForceAndSeesFloorAndWalls) {
  const Vec3 lo(3.5, -1.8, -0.3), hi(6.5, 1.6, 2.0);
  Esdf3dConfig config;
  config.max_distance_m = 1.5;
  Esdf3d<octomap::OcTree> esdf(*tree_, lo, hi, config);
  // Brute force over the occupied voxel centres in the box (the field sees only those).
  const MapVoxels voxels = octomap_to_voxels(*tree_, lo, hi);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(lo.x(), hi.x()), uy(lo.y(), hi.y()), uz(lo.z(), hi.z());
  double worst = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double z = uz(rng), y = uy(rng);  // z, y, x: the order of record (random_draws.hpp)
    const Vec3 p(ux(rng), y, z);
    const octomap::point3d c = tree_->keyToCoord(tree_->coordToKey(p.x(), p.y(), p.z()));
    const Vec3 centre(c.x(), c.y(), c.z());
    double best = esdf.max_distance_m();
    for (const MapVoxel& v : voxels) best = std::min(best, (v.center_W - centre).norm());
    const std::optional<double> d = esdf.voxel_distance(p);
    ASSERT_TRUE(d) << p.transpose();
    worst = std::max(worst, std::abs(*d - best));
  }
  EXPECT_LT(worst, 1e-4);
  RecordProperty("esdf3d_worst_error_m", std::to_string(worst));
  // On the corridor's centre line, 0.5 m over the floor: the floor is the nearest obstacle.
  const Vec3 above_floor(5.0, -0.1, 0.5);
  const double d = *esdf.distance(above_floor);
  RecordProperty("esdf3d_above_floor_m", std::to_string(d));
  EXPECT_GT(d, 0.4);
  EXPECT_LT(d, 0.65);
  EXPECT_GT(esdf.gradient(above_floor)->z(), 0.7);
  // In the lower wall (y = -1.44 at hip height): zero.
  int on_wall = 0, wall_voxels = 0;
  for (const MapVoxel& v : voxels) {
    if (std::abs(v.center_W.y() + 1.44) > 0.05 || v.center_W.z() < 0.5 || v.center_W.z() > 1.2) continue;
    ++wall_voxels;
    on_wall += *esdf.voxel_distance(v.center_W) == 0.0 ? 1 : 0;
  }
  EXPECT_GT(wall_voxels, 50);
  EXPECT_EQ(on_wall, wall_voxels);
}

}  // namespace
}  // namespace navaid::mapping
