// 2D ESDF against brute force, its gradients, scrolling; the 3D field on a small OcTree.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <octomap/OcTree.h>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"
#include "navaid/mapping/distance_transform.hpp"
#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/mapping/esdf_3d.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

// A cost map whose obstacles are the set cells of `mask` (cost 1, others 0).
CostMap cost_map_of(const GridGeometry& g, const ImageU8& mask) {
  CostMap c(g, 0.9, 0.0);
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) c.at(x, y) = mask.at(x, y) != 0 ? 1.0F : 0.0F;
  }
  return c;
}

ImageU8 random_mask(int w, int h, double density, unsigned seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution set(density);
  ImageU8 m(w, h, 1, 0);
  for (auto& v : m.pixels) v = set(rng) ? 1 : 0;
  return m;
}

// Signed distance of cell (x, y) by brute force [m].
double brute_signed_distance(const ImageU8& mask, int x, int y, double r) {
  const bool inside = mask.at(x, y) != 0;
  double best = std::numeric_limits<double>::infinity();
  for (int j = 0; j < mask.height; ++j) {
    for (int i = 0; i < mask.width; ++i) {
      if ((mask.at(i, j) != 0) == inside) continue;
      best = std::min(best, std::hypot(i - x, j - y));
    }
  }
  return inside ? -best * r : best * r;
}

TEST(Esdf2d, ExactAgainstBruteForceOnRandomGrids) {
  const GridGeometry g(Cell2(-7, 3), 37, 29, 0.1);
  for (const double density : {0.02, 0.1, 0.4, 0.8}) {
    const ImageU8 mask = random_mask(g.width(), g.height(), density, 17U + static_cast<unsigned>(density * 100));
    Esdf2d esdf;
    esdf.update(cost_map_of(g, mask));
    for (int y = 0; y < g.height(); ++y) {
      for (int x = 0; x < g.width(); ++x) {
        ASSERT_NEAR(esdf.field().at(x, y), brute_signed_distance(mask, x, y, 0.1), 1e-6)
            << "density " << density << " cell " << x << "," << y;
      }
    }
  }
}

TEST(Esdf2d, DynamicEdtBackendAgreesWithBruteForce) {
  // dynamicEDT3D's brushfire takes its distances from the obstacle it propagated: exact for that
  // obstacle, and that obstacle is the nearest on these grids (measured; see thirdparty-notes).
  const GridGeometry g(Cell2(0, 0), 37, 29, 0.1);
  Esdf2dConfig config;
  config.backend = DistanceTransformBackend::kDynamicEdt;
  for (const double density : {0.02, 0.1, 0.4}) {
    const ImageU8 mask = random_mask(g.width(), g.height(), density, 5U + static_cast<unsigned>(density * 100));
    Esdf2d esdf(config);
    esdf.update(cost_map_of(g, mask));
    double worst = 0.0;
    for (int y = 0; y < g.height(); ++y) {
      for (int x = 0; x < g.width(); ++x) {
        worst = std::max(worst, std::abs(esdf.field().at(x, y) - brute_signed_distance(mask, x, y, 0.1)));
      }
    }
    EXPECT_LT(worst, 1e-6) << "density " << density;
  }
}

TEST(Esdf2d, NoObstaclesIsInfiniteWithZeroGradient) {
  const GridGeometry g(Cell2(0, 0), 5, 5, 0.1);
  Esdf2d esdf;
  esdf.update(cost_map_of(g, ImageU8(5, 5, 1, 0)));
  EXPECT_TRUE(std::isinf(*esdf.distance(Vec2(0.25, 0.25))));
  EXPECT_EQ(*esdf.gradient(Vec2(0.25, 0.25)), Vec2::Zero());
  EXPECT_FALSE(esdf.distance(Vec2(0.51, 0.25)).has_value());
}

TEST(Esdf2d, BilinearDistanceAndStraightWallGradient) {
  // Obstacle column x = 0: outside, the field is exactly linear in x with slope 1.
  const GridGeometry g(Cell2(0, 0), 20, 10, 0.1);
  ImageU8 mask(20, 10, 1, 0);
  for (int y = 0; y < 10; ++y) mask.at(0, y) = 1;
  Esdf2d esdf;
  esdf.update(cost_map_of(g, mask));
  const Vec2 p(0.737, 0.42);  // 7.37 - 0.5 = 6.87 cells from the wall's centre
  EXPECT_NEAR(*esdf.distance(p), 0.687, 1e-6);
  EXPECT_NEAR(esdf.gradient(p)->x(), 1.0, 1e-6);
  EXPECT_NEAR(esdf.gradient(p)->y(), 0.0, 1e-6);
  // Zero crossing on the obstacle's face (x = 0.1): the obstacle cell reads -r, its neighbour +r.
  EXPECT_NEAR(esdf.field().at(0, 5), -0.1, 1e-7);
  EXPECT_NEAR(esdf.field().at(1, 5), 0.1, 1e-7);
  EXPECT_NEAR(*esdf.distance(Vec2(0.1, 0.55)), 0.0, 1e-7);
}

TEST(Esdf2d, GradientMatchesFiniteDifferencesAndPointsAwayFromTheObstacle) {
  const GridGeometry g(Cell2(0, 0), 61, 61, 0.1);
  ImageU8 mask(61, 61, 1, 0);
  mask.at(30, 30) = 1;
  Esdf2d esdf;
  esdf.update(cost_map_of(g, mask));
  const Vec2 obstacle = g.cell_center(Cell2(30, 30));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(0.5, 5.6);
  int checked = 0;
  while (checked < 200) {
    const Vec2 p = draw_vector<2>([&] { return coord(rng); });
    if ((p - obstacle).norm() < 0.8) continue;  // away from the cone's tip
    ++checked;
    const Vec2 grad = *esdf.gradient(p);
    // Finite differences of the distance query with a half-cell step.
    const double h = 0.05;
    const Vec2 fd((*esdf.distance(p + Vec2(h, 0)) - *esdf.distance(p - Vec2(h, 0))) / (2 * h),
                  (*esdf.distance(p + Vec2(0, h)) - *esdf.distance(p - Vec2(0, h))) / (2 * h));
    EXPECT_NEAR((grad - fd).norm(), 0.0, 0.03) << p.transpose();
    // And the true gradient of the distance to a point: the unit vector away from it.
    EXPECT_NEAR((grad - (p - obstacle).normalized()).norm(), 0.0, 0.03) << p.transpose();
    EXPECT_NEAR(*esdf.distance(p), (p - obstacle).norm(), 0.01) << p.transpose();
  }
}

TEST(Esdf2d, ScrollingEqualsRecomputation) {
  const GridConfig window{0.1, 6.0};
  // Obstacles near the user, inside both windows.
  const auto scene_cost = [](const GridGeometry& g) {
    CostMap c(g, 0.9, 0.0);
    for (int y = 0; y < g.height(); ++y) {
      for (int x = 0; x < g.width(); ++x) {
        const Vec2 p = g.cell_center(Cell2(x, y));
        const bool box = p.x() > 1.0 && p.x() < 1.6 && p.y() > -0.4 && p.y() < 0.9;
        const bool wall = p.y() > 1.3 && p.y() < 1.5 && p.x() > -0.5 && p.x() < 2.5;
        c.at(x, y) = box || wall ? 1.0F : 0.2F;
      }
    }
    return c;
  };
  const GridGeometry a = GridGeometry::around(Vec2(0.3, 0.2), window);
  const GridGeometry b = GridGeometry::around(Vec2(0.3 + 1.234, 0.2 - 0.461), window);
  ASSERT_NE(a, b);
  Esdf2d scrolled;
  scrolled.update(scene_cost(a));
  scrolled.update(scene_cost(b));
  Esdf2d fresh;
  fresh.update(scene_cost(b));
  ASSERT_EQ(scrolled.geometry(), b);
  EXPECT_EQ(scrolled.field().cells(), fresh.field().cells());
  // World-anchored: where both windows overlap, the same ground has the same value.
  Esdf2d first;
  first.update(scene_cost(a));
  int compared = 0;
  for (int y = 0; y < b.height(); ++y) {
    for (int x = 0; x < b.width(); ++x) {
      const Vec2 p = b.cell_center(Cell2(x, y));
      const Cell2 in_a = a.cell_of(p);
      if (!a.contains(in_a)) continue;
      ASSERT_FLOAT_EQ(first.field().at(in_a), fresh.field().at(x, y)) << p.transpose();
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(Esdf2d, BackendConfig) {
  EXPECT_EQ(read_esdf_2d_config(Config::parse("mapping: {esdf: {backend: dynamicedt3d}}")).backend,
            DistanceTransformBackend::kDynamicEdt);
  EXPECT_EQ(read_esdf_2d_config(Config()).backend, DistanceTransformBackend::kOpenCv);
  const std::string msg = testing::error_message<ConfigError>(
      [] { read_esdf_2d_config(Config::parse("mapping: {esdf: {backend: fmm}}")); });
  EXPECT_NE(msg.find("mapping.esdf.backend"), std::string::npos) << msg;
}

TEST(Esdf2d, EveryBackendRoundTripsThroughItsName) {
  // Every enumerator with its config spelling; a dropped or misspelt table entry fails.
  const std::vector<std::pair<DistanceTransformBackend, std::string>> backends{
      {DistanceTransformBackend::kOpenCv, "opencv"},
      {DistanceTransformBackend::kDynamicEdt, "dynamicedt3d"},
  };
  for (const auto& [backend, name] : backends) {
    EXPECT_EQ(to_string(backend), name);
    EXPECT_EQ(distance_transform_backend_from_string(to_string(backend)), backend) << name;
    EXPECT_EQ(read_esdf_2d_config(Config::parse("{}", "t", {"mapping.esdf.backend=" + name})).backend, backend)
        << name;
  }
  EXPECT_EQ(distance_transform_backend_from_string("OpenCV"), std::nullopt);
  EXPECT_EQ(distance_transform_backend_from_string("dynamicedt"), std::nullopt);
}

TEST(Esdf3d, DistanceToOneOccupiedVoxel) {
  octomap::OcTree tree(0.1);
  const octomap::point3d obstacle(0.05F, 0.05F, 0.05F);  // a voxel centre
  tree.updateNode(obstacle, true);
  Esdf3dConfig config;
  config.max_distance_m = 1.0;
  Esdf3d<octomap::OcTree> esdf(tree, Vec3(-1, -1, -1), Vec3(1, 1, 1), config);
  EXPECT_DOUBLE_EQ(*esdf.voxel_distance(Vec3(0.05, 0.05, 0.05)), 0.0);
  // Voxel (3, 4, 0) cells away: 0.5 m.
  EXPECT_NEAR(*esdf.voxel_distance(Vec3(0.35, 0.45, 0.05)), 0.5, 1e-6);
  EXPECT_NEAR(*esdf.distance(Vec3(0.35, 0.45, 0.05)), 0.5, 1e-6);
  EXPECT_FALSE(esdf.voxel_distance(Vec3(1.5, 0, 0)).has_value());
  // Gradient points away from the obstacle.
  const Vec3 p(0.45, 0.05, 0.05);
  const Vec3 grad = *esdf.gradient(p);
  EXPECT_NEAR(grad.x(), 1.0, 1e-6);
  EXPECT_NEAR(grad.y(), 0.0, 1e-6);
  EXPECT_NEAR(grad.z(), 0.0, 1e-6);
  EXPECT_TRUE(esdf.closest_obstacle(p)->isApprox(Vec3(0.05, 0.05, 0.05), 1e-6));
  // Saturation at max_distance_m.
  EXPECT_NEAR(*esdf.voxel_distance(Vec3(0.95, 0.95, 0.95)), esdf.max_distance_m(), 1e-6);
  // Incremental: a second obstacle nearer to p.
  tree.updateNode(octomap::point3d(0.65F, 0.05F, 0.05F), true);
  esdf.update();
  EXPECT_NEAR(*esdf.voxel_distance(p), 0.2, 1e-6);
}

TEST(Esdf3d, ConfigKeys) {
  const Esdf3dConfig c =
      read_esdf_3d_config(Config::parse("mapping: {esdf3d: {max_distance_m: 3, unknown_as_occupied: true}}"));
  EXPECT_DOUBLE_EQ(c.max_distance_m, 3.0);
  EXPECT_TRUE(c.unknown_as_occupied);
  EXPECT_THROW(read_esdf_3d_config(Config::parse("mapping: {esdf3d: {max_distance_m: 0}}")), ConfigError);
}

}  // namespace
}  // namespace navaid::mapping
