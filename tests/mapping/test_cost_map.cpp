// Cost map, eLabrador eq. (8), and its inflation by the horizontal position uncertainty.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/cost_map.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(CostMap, EquationEightOnHandComputedCells) {
  const GridGeometry g(Cell2(0, 0), 4, 1, 0.1);
  CollisionMap mt(g);
  UndulationMap mh(g);
  mt.at(0, 0) = 0.3F;  // flat: M_c = M_t
  mt.at(1, 0) = 0.3F;  // undulating: M_c = 0.3 * 0 + 1
  mh.at(1, 0) = 1;
  mt.at(2, 0) = kNaN;  // unknown, flat: unknown_cost
  mt.at(3, 0) = kNaN;  // unknown, undulating: 1
  mh.at(3, 0) = 1;
  CostMapConfig config;
  config.unknown_cost = 0.4;
  const CostMap c = build_cost_map(mt, mh, 0.0, config);
  EXPECT_FLOAT_EQ(c.at(0, 0), 0.3F);
  EXPECT_FLOAT_EQ(c.at(1, 0), 1.0F);
  EXPECT_FLOAT_EQ(c.at(2, 0), 0.4F);
  EXPECT_FLOAT_EQ(c.at(3, 0), 1.0F);
  EXPECT_DOUBLE_EQ(fused_cost(0.25, 0.0), 0.25);
  EXPECT_DOUBLE_EQ(fused_cost(0.25, 1.0), 1.0);
  EXPECT_TRUE(c.is_obstacle(1, 0));
  EXPECT_FALSE(c.is_obstacle(0, 0));
}

// A one-cell-wide wall (column 20) across a 41 x 41 grid, free ground elsewhere.
int blocked_cells_around_wall(double sigma_xy, const CostMapConfig& config) {
  const GridGeometry g(Cell2(0, 0), 41, 41, 0.1);
  CollisionMap mt(g);
  for (float& v : mt.cells().pixels) v = 0.0F;
  for (int y = 0; y < 41; ++y) mt.at(20, y) = 1.0F;
  const CostMap c = build_cost_map(mt, UndulationMap(g), sigma_xy, config);
  int blocked = 0;
  for (const float v : c.cells().pixels) blocked += v > config.obstacle_threshold ? 1 : 0;
  return blocked;
}

TEST(CostMap, LargerSigmaBlocksMoreCellsByTheExpectedCount) {
  const CostMapConfig config;  // k = 2, no base radius
  // r = 2 sigma; each row is blocked for 2 floor(r / 0.1) + 1 cells.
  const auto expected = [](double r_cells) { return 41 * (2 * static_cast<int>(std::floor(r_cells)) + 1); };
  EXPECT_EQ(blocked_cells_around_wall(0.0, config), 41);
  EXPECT_EQ(blocked_cells_around_wall(0.06, config), expected(1.2));   // 123
  EXPECT_EQ(blocked_cells_around_wall(0.16, config), expected(3.2));   // 287
  EXPECT_EQ(blocked_cells_around_wall(0.16, config) - blocked_cells_around_wall(0.06, config), 41 * 4);
  // A base radius adds to k sigma.
  CostMapConfig based = config;
  based.inflation_base_radius_m = 0.1;
  EXPECT_DOUBLE_EQ(inflation_radius_m(based, 0.06), 0.22);
  EXPECT_EQ(blocked_cells_around_wall(0.06, based), expected(2.2));
}

TEST(CostMap, InflationOfOnePointIsADisc) {
  const GridGeometry g(Cell2(0, 0), 11, 11, 0.1);
  CollisionMap mt(g);
  for (float& v : mt.cells().pixels) v = 0.0F;
  mt.at(5, 5) = 1.0F;
  // r = 2.5 cells: lattice points with dx^2 + dy^2 <= 6.25: 5 + 2 * 5 + 2 * 3 = 21.
  const CostMap c = build_cost_map(mt, UndulationMap(g), 0.125, CostMapConfig{});
  int blocked = 0;
  for (int y = 0; y < 11; ++y) {
    for (int x = 0; x < 11; ++x) {
      const bool in_disc = (x - 5) * (x - 5) + (y - 5) * (y - 5) <= 6;
      EXPECT_EQ(c.is_obstacle(x, y), in_disc) << x << "," << y;
      blocked += c.is_obstacle(x, y) ? 1 : 0;
    }
  }
  EXPECT_EQ(blocked, 21);
  EXPECT_DOUBLE_EQ(c.inflation_radius_m(), 0.25);
}

TEST(CostMap, NonFiniteOrNegativeSigmaIsAClearError) {
  const GridGeometry g(Cell2(0, 0), 3, 3, 0.1);
  const CollisionMap mt(g);
  const UndulationMap mh(g);
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -0.1}) {
    const std::string msg =
        testing::error_message<Error>([&] { build_cost_map(mt, mh, bad, CostMapConfig{}); }, std::to_string(bad));
    EXPECT_NE(msg.find("sigma_xy"), std::string::npos) << msg;
  }
}

TEST(CostMap, ConfigKeysAndRanges) {
  const CostMapConfig c = read_cost_map_config(Config::parse(R"(
mapping:
  cost: {unknown_cost: 0.7, obstacle_threshold: 0.8}
  inflation: {k_sigma: 3, base_radius_m: 0.2}
)"));
  EXPECT_DOUBLE_EQ(c.unknown_cost, 0.7);
  EXPECT_DOUBLE_EQ(c.obstacle_threshold, 0.8);
  EXPECT_DOUBLE_EQ(c.inflation_k_sigma, 3.0);
  EXPECT_DOUBLE_EQ(c.inflation_base_radius_m, 0.2);
  const std::string msg = testing::error_message<ConfigError>(
      [] { read_cost_map_config(Config::parse("mapping: {inflation: {k_sigma: -1}}")); });
  EXPECT_NE(msg.find("mapping.inflation.k_sigma"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::mapping
