// The map window's grid: snapped to whole cells, so scrolling keeps cell boundaries; footprints of
// voxels larger and smaller than a cell.
#include <gtest/gtest.h>

#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/grid_geometry.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

TEST(GridGeometry, WindowIsSnappedToWholeCells) {
  const GridConfig config;  // 10 m at 0.1 m
  const GridGeometry a = GridGeometry::around(Vec2(3.07, -1.92), config);
  EXPECT_EQ(a.width(), 100);
  EXPECT_EQ(a.height(), 100);
  // The user's cell (30, -20) is cell (50, 50) of the window.
  EXPECT_EQ(a.cell_of(Vec2(3.07, -1.92)), Cell2(50, 50));
  EXPECT_EQ(a.origin_cell(), Cell2(-20, -70));
  EXPECT_NEAR(a.origin_W().x(), -2.0, 1e-12);
  EXPECT_NEAR(a.cell_center(Cell2(0, 0)).x(), -1.95, 1e-12);
  // Moved by 1.234 m: the window moves by whole cells and a world point keeps its world cell.
  const GridGeometry b = GridGeometry::around(Vec2(3.07 + 1.234, -1.92 - 0.5), config);
  const Cell2 shift = b.origin_cell() - a.origin_cell();
  EXPECT_EQ(shift, Cell2(13, -5));
  const Vec2 p(4.0, -0.3);
  EXPECT_EQ(a.cell_of(p) - shift, b.cell_of(p));
  EXPECT_EQ(a.cell_center(a.cell_of(p)), b.cell_center(b.cell_of(p)));
}

TEST(GridGeometry, ContinuousCoordinatesPutCellCentresOnIntegers) {
  const GridGeometry g(Cell2(-5, 2), 10, 8, 0.2);
  const Vec2 u = g.continuous_cell(g.cell_center(Cell2(3, 4)));
  EXPECT_NEAR(u.x(), 3.0, 1e-12);
  EXPECT_NEAR(u.y(), 4.0, 1e-12);
  EXPECT_TRUE(g.contains(Cell2(9, 7)));
  EXPECT_FALSE(g.contains(Cell2(10, 0)));
  EXPECT_FALSE(g.contains(Cell2(0, -1)));
}

TEST(GridGeometry, FootprintOfLargeAndSmallVoxels) {
  const GridGeometry g(Cell2(0, 0), 6, 6, 0.1);
  std::vector<Cell2> cells;
  const auto collect = [&](const Cell2& c) { cells.push_back(c); };
  // 0.2 m voxel centred on a cell corner covers the four cells around it.
  for_each_footprint_cell(g, Vec3(0.2, 0.3, 0.0), 0.2, collect);
  EXPECT_EQ(cells, (std::vector<Cell2>{Cell2(1, 2), Cell2(2, 2), Cell2(1, 3), Cell2(2, 3)}));
  // 0.08 m voxel that covers no cell centre: the cell holding its centre.
  cells.clear();
  for_each_footprint_cell(g, Vec3(0.205, 0.105, 0.0), 0.08, collect);
  EXPECT_EQ(cells, (std::vector<Cell2>{Cell2(2, 1)}));
  // Partly outside the grid: only the inside cells.
  cells.clear();
  for_each_footprint_cell(g, Vec3(0.0, 0.0, 0.0), 0.2, collect);
  EXPECT_EQ(cells, (std::vector<Cell2>{Cell2(0, 0)}));
}

TEST(GridGeometry, ConfigKeysAndRanges) {
  const GridConfig g = read_grid_config(Config::parse("mapping: {grid: {resolution_m: 0.05, size_m: 8}}"));
  EXPECT_DOUBLE_EQ(g.resolution_m, 0.05);
  EXPECT_DOUBLE_EQ(g.size_m, 8.0);
  const std::string too_fine = testing::error_message<ConfigError>(
      [] { read_grid_config(Config::parse("mapping: {grid: {resolution_m: 0.001}}", "m.yaml")); });
  EXPECT_NE(too_fine.find("mapping.grid.resolution_m"), std::string::npos) << too_fine;
  const std::string too_small = testing::error_message<ConfigError>(
      [] { read_grid_config(Config::parse("mapping: {grid: {resolution_m: 0.5, size_m: 1}}", "m.yaml")); });
  EXPECT_NE(too_small.find("3 x 3"), std::string::npos) << too_small;
}

}  // namespace
}  // namespace navaid::mapping
