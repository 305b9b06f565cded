#include "navaid/simulation/occupancy_export.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

AxisAlignedBox cube(double lo, double hi) {
  AxisAlignedBox b;
  b.extend(Vec3::Constant(lo));
  b.extend(Vec3::Constant(hi));
  return b;
}

Box aabb(const Vec3& lo, const Vec3& hi) { return Box{SE3(Quat::Identity(), 0.5 * (lo + hi)), 0.5 * (hi - lo)}; }

std::size_t count(const Shape& shape, double res = 0.1, const AxisAlignedBox& bounds = cube(-1.0, 2.0)) {
  World w;
  w.add(shape, Surface{SemanticClass::kCar});
  return voxelize(w, res, bounds).count_occupied();
}

TEST(Voxelize, AxisAlignedBoxesGiveKnownCounts) {
  // Offset box: 11 x 6 x 4 cells touched.
  EXPECT_EQ(count(aabb(Vec3(0.05, 0.05, 0.05), Vec3(1.05, 0.55, 0.35))), 11u * 6u * 4u);
  // Grid-aligned box: exactly its 10 x 5 x 5 cells; neighbours that only touch a face stay free.
  EXPECT_EQ(count(aabb(Vec3(0.2, 0.3, 0.0), Vec3(1.2, 0.8, 0.5))), 250u);
  // A box rotated by 90 degrees about z is the same set.
  EXPECT_EQ(count(Box{SE3(quat_from_rpy(0, 0, M_PI / 2), Vec3(0.5, 0.5, 0.25)), Vec3(0.25, 0.5, 0.25)}),
            count(aabb(Vec3(0.0, 0.25, 0.0), Vec3(1.0, 0.75, 0.5))));
}

TEST(Voxelize, RotatedBoxCoversItsVolume) {
  // A 45-degree square of side 1 m: occupied area between the true area and area + perimeter x
  // cell diagonal (cells straddling the edges).
  const std::size_t n = count(Box{SE3(quat_from_rpy(0, 0, M_PI / 4), Vec3(0.5, 0.5, 0.05)), Vec3(0.5, 0.5, 0.05)});
  EXPECT_GE(n * 0.01, 1.0);
  EXPECT_LE(n * 0.01, 1.0 + 4.0 * 0.1 * std::sqrt(2.0));
}

TEST(Voxelize, SpheresEllipsoidsAndCylindersAroundACellCentre) {
  const Vec3 c(0.05, 0.05, 0.05);  // centre of cell (10, 10, 10) of the grid starting at -1
  auto sphere = [&](double r) { return Ellipsoid{SE3(Quat::Identity(), c), Vec3::Constant(r)}; };
  // Nearest points of the neighbours: faces 0.05, edges 0.0707, corners 0.0866 m away.
  EXPECT_EQ(count(sphere(0.1)), 27u);
  EXPECT_EQ(count(sphere(0.08)), 19u);
  EXPECT_EQ(count(sphere(0.06)), 7u);
  // Ellipsoid 0.06 x 0.2 x 0.06: five cells along y on the axis, three along y beside it.
  EXPECT_EQ(count(Ellipsoid{SE3(Quat::Identity(), c), Vec3(0.06, 0.2, 0.06)}), 17u);
  EXPECT_EQ(count(Ellipsoid{SE3(quat_from_rpy(0, 0, M_PI / 2), c), Vec3(0.2, 0.06, 0.06)}), 17u);
  // Cylinder of radius 0.1 / 0.06 over three layers: 9 / 5 columns.
  EXPECT_EQ(count(VerticalCylinder{Vec3(0.05, 0.05, 0.0), 0.1, 0.3}), 27u);
  EXPECT_EQ(count(VerticalCylinder{Vec3(0.05, 0.05, 0.0), 0.06, 0.3}), 15u);
}

TEST(Voxelize, ExtrudedTriangleAndPlanePatches) {
  // Right triangle with 1 m legs, one layer: cells (i, j) with i + j <= 9.
  EXPECT_EQ(count(ExtrudedPolygon{{Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}, 0.0, 0.1}), 55u);
  // A horizontal patch inside a layer and one on a layer boundary (half-open cells: the upper one).
  World w;
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0.5, 0.5, 0.25)), 0.45, 0.45}, Surface{SemanticClass::kFloor});
  w.add(PlanePatch{SE3(Quat::Identity(), Vec3(0.5, 0.5, 0.0)), 0.45, 0.45}, Surface{SemanticClass::kRoad});
  const OccupancyGrid3D g = voxelize(w, 0.1, cube(-1.0, 2.0));
  EXPECT_EQ(g.count_occupied(), 200u);
  EXPECT_EQ(g.cells[g.index(15, 15, 12)], static_cast<std::uint8_t>(SemanticClass::kFloor));
  EXPECT_EQ(g.cells[g.index(15, 15, 10)], static_cast<std::uint8_t>(SemanticClass::kRoad));
  EXPECT_FALSE(g.occupied(15, 15, 9));
}

TEST(Voxelize, LastPrimitiveKeepsItsClassAndGridGeometry) {
  World w;
  w.add(aabb(Vec3(0, 0, 0), Vec3(0.4, 0.4, 0.4)), Surface{SemanticClass::kCar});
  w.add(aabb(Vec3(0.2, 0.2, 0.2), Vec3(0.6, 0.6, 0.6)), Surface{SemanticClass::kPerson});
  AxisAlignedBox b;
  b.extend(Vec3(0, 0, 0));
  b.extend(Vec3(1.0, 0.55, 0.6));
  const OccupancyGrid3D g = voxelize(w, 0.1, b);
  EXPECT_EQ(g.size, Eigen::Vector3i(10, 6, 6));  // 0.55 m needs a sixth cell
  EXPECT_TRUE(g.center(0, 0, 0).isApprox(Vec3(0.05, 0.05, 0.05)));
  EXPECT_EQ(g.cells[g.index(0, 0, 0)], static_cast<std::uint8_t>(SemanticClass::kCar));
  EXPECT_EQ(g.cells[g.index(3, 3, 3)], static_cast<std::uint8_t>(SemanticClass::kPerson));
  EXPECT_EQ(g.count_occupied(), 64u + 64u - 8u);
}

TEST(Voxelize, RejectsBadArguments) {
  World w;
  EXPECT_THROW(voxelize(w, 0.0, cube(0, 1)), Error);
  EXPECT_THROW(voxelize(w, 0.1, AxisAlignedBox()), Error);
  EXPECT_THROW(voxelize(w, 1e-4, cube(0, 200)), Error);  // too many voxels
}

TEST(OccupancyMap, PgmAndYamlInMapServerFormat) {
  World w;
  w.add(aabb(Vec3(1.6, 0.8, 0.0), Vec3(2.0, 1.0, 1.0)), Surface{SemanticClass::kWall});  // top-right corner
  w.add(aabb(Vec3(0.0, 0.0, 1.5), Vec3(0.5, 0.5, 2.0)), Surface{SemanticClass::kWall});  // above the slice
  AxisAlignedBox b;
  b.extend(Vec3(0, 0, 0));
  b.extend(Vec3(2.0, 1.0, 2.0));
  const OccupancyGrid3D g = voxelize(w, 0.1, b);
  const ImageU8 slice = occupancy_slice(g, 0.2, 1.2);
  ASSERT_EQ(slice.width, 20);
  ASSERT_EQ(slice.height, 10);
  EXPECT_EQ(slice.at(19, 0), 0);    // high y is row 0
  EXPECT_EQ(slice.at(16, 1), 0);
  EXPECT_EQ(slice.at(15, 0), 254);
  EXPECT_EQ(slice.at(19, 2), 254);
  EXPECT_EQ(slice.at(0, 9), 254);   // the high box is outside the slice

  testing::ScratchDir dir("occupancy_map");
  write_occupancy_map(g, 0.2, 1.2, (dir / "map").string());
  std::ifstream pgm(dir / "map.pgm", std::ios::binary);
  std::string magic;
  int width = 0, height = 0, maxval = 0;
  pgm >> magic >> width >> height >> maxval;
  pgm.get();
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(width, 20);
  EXPECT_EQ(height, 10);
  EXPECT_EQ(maxval, 255);
  std::vector<char> data(200);
  pgm.read(data.data(), 200);
  ASSERT_EQ(pgm.gcount(), 200);
  EXPECT_EQ(std::vector<std::uint8_t>(data.begin(), data.end()), slice.pixels);
  const std::string yaml = testing::read_text(dir / "map.yaml");
  EXPECT_NE(yaml.find("image: map.pgm\n"), std::string::npos);
  EXPECT_NE(yaml.find("resolution: 0.1\n"), std::string::npos);
  EXPECT_NE(yaml.find("origin: [0, 0, 0.0]\n"), std::string::npos);
  EXPECT_NE(yaml.find("negate: 0\n"), std::string::npos);
  EXPECT_NE(yaml.find("occupied_thresh: 0.65\n"), std::string::npos);
  EXPECT_NE(yaml.find("free_thresh: 0.196\n"), std::string::npos);
  EXPECT_THROW(write_occupancy_map(g, 0.2, 1.2, (dir / "missing" / "map").string()), IoError);
}

TEST(OccupancyMap, VoxelCsvListsOccupiedCells) {
  World w;
  w.add(aabb(Vec3(0.1, 0.2, 0.0), Vec3(0.3, 0.3, 0.1)), Surface{SemanticClass::kTreeTrunk});
  const OccupancyGrid3D g = voxelize(w, 0.1, cube(0.0, 0.5));
  testing::ScratchDir dir("voxel_csv");
  write_voxel_csv(g, (dir / "v.csv").string());
  std::istringstream in(testing::read_text(dir / "v.csv"));
  std::string line;
  std::vector<std::string> rows;
  std::getline(in, line);
  EXPECT_EQ(line, "# navaid voxel list v1");
  while (std::getline(in, line))
    if (line.rfind('#', 0) != 0) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u);  // column line + 2 voxels
  EXPECT_EQ(rows[0], "ix,iy,iz,x,y,z,class");
  EXPECT_EQ(rows[1], "1,2,0,0.15,0.25,0.05,tree-trunk");
  EXPECT_EQ(rows[2], "2,2,0,0.25,0.25,0.05,tree-trunk");
}

}  // namespace
}  // namespace navaid::simulation
