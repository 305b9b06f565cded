// Undulation map: Sobel on the height map, thresholded; hand-made steps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/undulation_map.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

// 7 x 7 height map: 0 for x < 3, `step` for x >= 3.
HeightMap step_map(float step) {
  HeightMap h(GridGeometry(Cell2(0, 0), 7, 7, 0.1));
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 7; ++x) h.at(x, y) = x < 3 ? 0.0F : step;
  }
  return h;
}

TEST(UndulationMap, StepMarksTheTwoColumnsBesideIt) {
  const HeightMap h = step_map(0.2F);
  // Sobel at x = 2 and x = 3: (1 + 2 + 1) * 0.2 / 4 = 0.2 m; one column away nothing changes.
  EXPECT_NEAR(sobel_edge_degree(h, Cell2(2, 3)), 0.2, 1e-7);
  EXPECT_NEAR(sobel_edge_degree(h, Cell2(3, 3)), 0.2, 1e-7);
  EXPECT_NEAR(sobel_edge_degree(h, Cell2(1, 3)), 0.0, 1e-12);
  EXPECT_NEAR(sobel_edge_degree(h, Cell2(4, 3)), 0.0, 1e-12);
  const UndulationMap u = build_undulation_map(h, UndulationConfig{});
  for (int y = 0; y < 7; ++y) {
    for (int x = 0; x < 7; ++x) EXPECT_EQ(u.at(x, y), (x == 2 || x == 3) ? 1 : 0) << x << "," << y;
  }
}

TEST(UndulationMap, ThresholdIsStrictAndLowStepsPass) {
  // A one-voxel terrace (0.1 m) stays below the 0.12 m default.
  const UndulationMap low = build_undulation_map(step_map(0.1F), UndulationConfig{});
  for (const auto v : low.cells().pixels) EXPECT_EQ(v, 0);
  // Exactly at the threshold is not "beyond" it.
  UndulationConfig at;
  at.step_threshold_m = 0.25;
  const UndulationMap equal = build_undulation_map(step_map(0.25F), at);
  for (const auto v : equal.cells().pixels) EXPECT_EQ(v, 0);
  at.step_threshold_m = 0.2499;
  EXPECT_EQ(build_undulation_map(step_map(0.25F), at).at(2, 3), 1);
}

TEST(UndulationMap, UnknownCellsAreNoEvidenceOfAStep) {
  HeightMap h(GridGeometry(Cell2(0, 0), 5, 5, 0.1));
  for (float& v : h.cells().pixels) v = 0.3F;
  h.at(2, 2) = std::numeric_limits<float>::quiet_NaN();  // a hole in the data
  const UndulationMap u = build_undulation_map(h, UndulationConfig{});
  for (const auto v : u.cells().pixels) EXPECT_EQ(v, 0);
  EXPECT_EQ(sobel_edge_degree(h, Cell2(2, 2)), 0.0);
  // A flat map at any height has no edges, also at the border.
  EXPECT_EQ(sobel_edge_degree(h, Cell2(0, 0)), 0.0);
}

TEST(UndulationMap, ConfigKeyAndRange) {
  EXPECT_DOUBLE_EQ(
      read_undulation_config(Config::parse("mapping: {undulation: {step_threshold_m: 0.05}}")).step_threshold_m, 0.05);
  const std::string msg = testing::error_message<ConfigError>(
      [] { read_undulation_config(Config::parse("mapping: {undulation: {step_threshold_m: 3}}")); });
  EXPECT_NE(msg.find("mapping.undulation.step_threshold_m"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::mapping
