#include "navaid/simulation/world.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/semantic_classes.hpp"

namespace navaid::simulation {
namespace {

TEST(SemanticClasses, IdsAreStableAndNamesUnique) {
  const auto& classes = semantic_classes();
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < classes.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(classes[i].id), i);
    EXPECT_TRUE(names.insert(classes[i].name).second) << classes[i].name;
    EXPECT_EQ(semantic_class_from_name(classes[i].name), classes[i].id);
  }
  // Stable ids written into label images: never renumber.
  EXPECT_EQ(static_cast<int>(SemanticClass::kUnlabeled), 0);
  EXPECT_EQ(static_cast<int>(SemanticClass::kSky), 18);
  EXPECT_EQ(static_cast<int>(SemanticClass::kTactilePaving), 24);
  EXPECT_EQ(semantic_class_from_name("tree-trunk"), SemanticClass::kTreeTrunk);
  EXPECT_EQ(semantic_class_name(SemanticClass::kTrafficSign), "traffic-sign");
  EXPECT_EQ(static_cast<int>(SemanticClass::kTargetObject), 25);  // appended for hand guidance
  EXPECT_EQ(semantic_class_name(SemanticClass::kTargetObject), "target-object");
  EXPECT_TRUE(is_valid_semantic_id(25));
  EXPECT_FALSE(is_valid_semantic_id(26));
}

TEST(SemanticClasses, UnknownNameThrowsWithKnownList) {
  try {
    semantic_class_from_name("Sidewalk");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "semantic_class");
    EXPECT_NE(std::string(e.what()).find("sidewalk"), std::string::npos);
  }
}

TEST(World, TriangulatesEveryPrimitiveWithOutwardNormals) {
  World w;
  const Surface s{SemanticClass::kBuilding, 1, 0.2, 0.7};
  w.add(PlanePatch{SE3(), 2.0, 3.0}, s);
  w.add(Box{SE3(quat_from_rpy(0.1, 0.2, 0.3), Vec3(1, 2, 3)), Vec3(0.5, 1.0, 1.5)}, s);
  w.add(VerticalCylinder{Vec3(4, 0, 0), 0.2, 2.0}, s);
  w.add(Ellipsoid{SE3(quat_from_rpy(0.3, 0.0, 1.0), Vec3(-3, 1, 2)), Vec3(1.0, 0.5, 0.8)}, s);
  // L-shaped (non-convex), clockwise.
  w.add(ExtrudedPolygon{{{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}}, 0.0, 0.5}, s);
  const Tessellation tess{16, 12, 8};
  const TriangleMesh m = w.triangulate(tess);
  ASSERT_EQ(m.triangles.size(), m.triangle_primitive.size());
  std::vector<int> count(w.size(), 0);
  for (auto p : m.triangle_primitive) ++count[p];
  EXPECT_EQ(count[0], 2);
  EXPECT_EQ(count[1], 12);
  EXPECT_EQ(count[2], 16 * 4);
  EXPECT_EQ(count[3], 2 * 12 + 12 * (8 - 2) * 2);
  EXPECT_EQ(count[4], 6 * 2 + 2 * 4);

  // Closed shapes: signed volume from the divergence theorem is positive (outward winding) and
  // equals the analytic volume for flat-faced ones.
  std::vector<double> volume(w.size(), 0.0);
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    volume[m.triangle_primitive[i]] += m.vertices[t[0]].dot(m.vertices[t[1]].cross(m.vertices[t[2]])) / 6.0;
  }
  EXPECT_NEAR(volume[1], 8 * 0.5 * 1.0 * 1.5, 1e-12);
  EXPECT_GT(volume[2], 0.9 * 3.14159 * 0.04 * 2.0);
  EXPECT_LT(volume[2], 3.14159 * 0.04 * 2.0);
  EXPECT_GT(volume[3], 0.8 * 4.0 / 3.0 * 3.14159 * 0.4);
  EXPECT_NEAR(volume[4], 3.0 * 0.5, 1e-12);
  // Plane patch normal is +z.
  const auto& t0 = m.triangles[0];
  EXPECT_GT((m.vertices[t0[1]] - m.vertices[t0[0]]).cross(m.vertices[t0[2]] - m.vertices[t0[0]]).z(), 0.0);
}

TEST(World, BoundsAreExact) {
  World w;
  const Surface s{SemanticClass::kTreeTrunk, 0, 0.2, 0.7};
  w.add(VerticalCylinder{Vec3(1, 2, 0), 0.5, 3.0}, s);
  w.add(Ellipsoid{SE3(Quat::Identity(), Vec3(0, 0, 5)), Vec3(1, 2, 0.5)}, s);
  w.add(Box{SE3(quat_from_rpy(0, 0, 0.7853981633974483), Vec3(-4, 0, 0)), Vec3(1, 1, 1)}, s);
  const AxisAlignedBox b = w.bounds();
  ASSERT_FALSE(b.empty);
  EXPECT_NEAR(b.min.x(), -4 - std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(b.max.x(), 1.5, 1e-12);
  EXPECT_NEAR(b.min.y(), -2.0, 1e-12);
  EXPECT_NEAR(b.max.y(), 2.5, 1e-12);
  EXPECT_NEAR(b.min.z(), -1.0, 1e-12);
  EXPECT_NEAR(b.max.z(), 5.5, 1e-12);
  EXPECT_TRUE(World().bounds().empty);
}

TEST(World, RejectsInvalidPrimitives) {
  World w;
  const Surface s{SemanticClass::kWall, 0, 0.2, 0.7};
  EXPECT_THROW(w.add(Box{SE3(), Vec3(1, 0, 1)}, s), Error);
  EXPECT_THROW(w.add(VerticalCylinder{Vec3::Zero(), -1.0, 1.0}, s), Error);
  EXPECT_THROW(w.add(ExtrudedPolygon{{{0, 0}, {1, 1}}, 0, 1}, s), Error);
  EXPECT_THROW(w.add(ExtrudedPolygon{{{0, 0}, {1, 0}, {1, 1}}, 1, 1}, s), Error);
  EXPECT_THROW(w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{SemanticClass::kWall, 0, 0.0, 0.7}), Error);
  EXPECT_THROW(w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{static_cast<SemanticClass>(200), 0, 0.2, 0.7}), Error);
  EXPECT_TRUE(w.empty());
  EXPECT_THROW(w.triangulate(Tessellation{2, 8, 8}), Error);
}

}  // namespace
}  // namespace navaid::simulation
