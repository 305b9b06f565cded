#include "navaid/simulation/ray_caster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navaid/core/random_draws.hpp"

namespace navaid::simulation {
namespace {


Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return draw_vector<3>([&] { return n(rng); }).normalized();
}

TEST(RayCaster, EmptyWorldNeverHits) {
  const RayCaster rc{World()};
  EXPECT_FALSE(rc.cast(Vec3::Zero(), Vec3::UnitX()).has_value());
}

TEST(RayCaster, GroundPlaneHitIsExactInDouble) {
  World w;
  w.add(PlanePatch{SE3(), 100.0, 100.0}, Surface{SemanticClass::kSidewalk, 3, 0.2, 0.7});
  const RayCaster rc(w);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const double z = 0.5 + std::abs(u(rng)) * 3.0, y = 10 * u(rng);  // z, y, x: the order of record (random_draws.hpp)
    const Vec3 o(10 * u(rng), y, z);
    Vec3 d = random_unit(rng);
    d.z() = -std::abs(d.z()) - 0.05;
    d.normalize();
    const auto h = rc.cast(o, d);
    const double expected = -o.z() / d.z();
    if (std::abs((o + expected * d).x()) > 99 || std::abs((o + expected * d).y()) > 99) continue;
    ASSERT_TRUE(h.has_value());
    EXPECT_NEAR(h->distance, expected, 1e-12 * expected);
    EXPECT_NEAR(h->point.z(), 0.0, 1e-12);
    EXPECT_NEAR(h->normal.z(), 1.0, 1e-12);
    EXPECT_EQ(h->semantic, SemanticClass::kSidewalk);
    EXPECT_EQ(h->primitive, 0u);
  }
  // Looking up: no hit; range limits.
  EXPECT_FALSE(rc.cast(Vec3(0, 0, 1), Vec3::UnitZ()).has_value());
  EXPECT_FALSE(rc.cast(Vec3(0, 0, 1), -Vec3::UnitZ(), 0.99).has_value());
  EXPECT_TRUE(rc.cast(Vec3(0, 0, 1), -Vec3::UnitZ(), 1.01).has_value());
  EXPECT_FALSE(rc.cast(Vec3(0, 0, 1), -Vec3::UnitZ(), 5.0, 1.01).has_value());
}

// Analytic slab test for an oriented box.
double box_distance(const Box& b, const Vec3& o_W, const Vec3& d_W) {
  const SE3 T_O_W = b.T_W_O.inverse();
  const Vec3 o = T_O_W * o_W, d = T_O_W.q * d_W;
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    const double a = (-b.half_extents[k] - o[k]) / d[k], c = (b.half_extents[k] - o[k]) / d[k];
    t0 = std::max(t0, std::min(a, c));
    t1 = std::min(t1, std::max(a, c));
  }
  return t0 <= t1 && t0 > 0 ? t0 : -1.0;
}

TEST(RayCaster, BoxDistancesMatchSlabTest) {
  const Box box{SE3(quat_from_rpy(0.2, -0.3, 0.9), Vec3(1.0, 2.0, 0.5)), Vec3(0.7, 0.4, 1.1)};
  World w;
  w.add(box, Surface{SemanticClass::kBench, 0, 0.2, 0.7});
  const RayCaster rc(w);
  std::mt19937 rng(2);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const Vec3 o = box.T_W_O.t + 4.0 * random_unit(rng);
    const Vec3 target = box.T_W_O.t + 0.6 * random_unit(rng);
    const Vec3 d = (target - o).normalized();
    const double expected = box_distance(box, o, d);
    const auto h = rc.cast(o, d);
    if (expected < 0) continue;
    ASSERT_TRUE(h.has_value());
    ++hits;
    EXPECT_NEAR(h->distance, expected, 1e-9);
    EXPECT_LT(h->normal.dot(d), 0.0);  // outward normal faces the ray
    // The hit lies on a face plane of the box.
    const Vec3 p_O = box.T_W_O.inverse() * h->point;
    EXPECT_NEAR((p_O.cwiseAbs() - box.half_extents).maxCoeff(), 0.0, 1e-9);
  }
  EXPECT_GT(hits, 100);
}

TEST(RayCaster, EllipsoidDistancesMatchAnalyticWithinTessellation) {
  const Ellipsoid e{SE3(quat_from_rpy(0.4, 0.1, -0.5), Vec3(-1.0, 0.5, 2.0)), Vec3(1.0, 0.6, 0.8)};
  World w;
  w.add(e, Surface{SemanticClass::kVegetation, 0, 0.2, 0.7});
  const int n = 128;
  const RayCaster rc(w, Tessellation{24, 2 * n, n});
  // Chordal error of the inscribed tessellation is <= r_max (1 - cos(pi / n)) per direction.
  const double tol = 2.0 * e.radii.maxCoeff() * (1.0 - std::cos(M_PI / n)) + 1e-9;
  std::mt19937 rng(3);
  for (int i = 0; i < 300; ++i) {
    const Vec3 o = e.T_W_O.t + 5.0 * random_unit(rng);
    const Vec3 target = e.T_W_O.t + 0.3 * random_unit(rng);
    const Vec3 d = (target - o).normalized();
    // Analytic: |S^-1 R^T (o + t d - c)| = 1.
    const SE3 T_O_W = e.T_W_O.inverse();
    const Vec3 oo = (T_O_W * o).cwiseQuotient(e.radii), dd = (T_O_W.q * d).cwiseQuotient(e.radii);
    const double a = dd.squaredNorm(), b = 2 * oo.dot(dd), c = oo.squaredNorm() - 1.0;
    const double expected = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
    const auto h = rc.cast(o, d);
    ASSERT_TRUE(h.has_value());
    EXPECT_GE(h->distance, expected - 1e-9);  // inscribed mesh: never in front of the surface
    EXPECT_NEAR(h->distance, expected, tol);
    EXPECT_EQ(h->semantic, SemanticClass::kVegetation);
  }
  // Sphere through its centre: distance = |o - c| - r within tessellation error.
  World ws;
  ws.add(Ellipsoid{SE3(Quat::Identity(), Vec3(3, 0, 1)), Vec3::Constant(0.5)}, Surface{SemanticClass::kPerson, 0, 0.2, 0.7});
  const RayCaster rs(ws, Tessellation{24, 2 * n, n});
  const auto h = rs.cast(Vec3(0, 0, 1), Vec3::UnitX());
  ASSERT_TRUE(h.has_value());
  EXPECT_NEAR(h->distance, 2.5, 0.5 * (1.0 - std::cos(M_PI / n)) + 1e-9);
}

TEST(RayCaster, BatchMatchesSingleAndReportsPrimitive) {
  World w;
  w.add(PlanePatch{SE3(), 20.0, 20.0}, Surface{SemanticClass::kFloor, 0, 0.2, 0.7});
  w.add(VerticalCylinder{Vec3(2, 0, 0), 0.3, 2.0}, Surface{SemanticClass::kPole, 0, 0.2, 0.7});
  const RayCaster rc(w);
  std::vector<Vec3> dirs;
  std::mt19937 rng(4);
  for (int i = 0; i < 100; ++i) dirs.push_back(random_unit(rng));
  dirs.push_back(Vec3::UnitX());
  std::vector<std::optional<Hit>> hits;
  const Vec3 o(0, 0, 1);
  rc.cast_batch(o, dirs, hits);
  ASSERT_EQ(hits.size(), dirs.size());
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const auto single = rc.cast(o, dirs[i]);
    ASSERT_EQ(single.has_value(), hits[i].has_value());
    if (single) {
      EXPECT_EQ(single->distance, hits[i]->distance);
      EXPECT_EQ(single->primitive, hits[i]->primitive);
    }
  }
  ASSERT_TRUE(hits.back().has_value());
  EXPECT_EQ(hits.back()->primitive, 1u);
  EXPECT_EQ(hits.back()->semantic, SemanticClass::kPole);
  EXPECT_NEAR(hits.back()->distance, 1.7, 1e-9);  // a vertex of the 24-gon lies on +x
}

}  // namespace
}  // namespace navaid::simulation
