// Tagged target objects (hand guidance): the image texture of a plane patch, the lab walks' box
// with its AprilTag (label image, printed code bits, ground truth in targets.csv), and the one-way
// label confusion that keeps the table's row as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "pinhole_calibration.hpp"
#include "navaid/core/camera.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/io/targets_csv.hpp"
#include "navaid/simulation/apriltag_image.hpp"
#include "navaid/simulation/label_confusion_model.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/simulation_config.hpp"
#include "navaid/simulation/simulator.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

// Camera at `eye` looking at `target`, image x right, y down, with W z up.
SE3 camera_looking_at(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  Vec3 x = z.cross(Vec3::UnitZ());
  x.normalize();
  const Vec3 y = z.cross(x);
  Mat3 R;
  R << x, y, z;
  return SE3(R, eye);
}

const TargetObject& lab_target(const Scenario& s) {
  EXPECT_EQ(s.targets.size(), 1u);
  return s.targets.front();
}

TEST(ImageTexture, OnlyOnPlanePatchesAndOneChannel) {
  World w;
  auto grey = std::make_shared<const ImageU8>(4, 4, 1, std::uint8_t{0});
  EXPECT_NO_THROW(w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{}, grey));
  EXPECT_NE(w.image_texture(0), nullptr);
  EXPECT_THROW(w.add(Box{SE3(), Vec3::Ones()}, Surface{}, grey), Error);
  EXPECT_THROW(w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{}, std::make_shared<const ImageU8>(4, 4, 3)), Error);
  EXPECT_THROW(w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{}, std::make_shared<const ImageU8>()), Error);
  w.add(PlanePatch{SE3(), 1.0, 1.0}, Surface{});
  EXPECT_EQ(w.image_texture(1), nullptr);  // a failed add leaves nothing behind
  EXPECT_EQ(w.size(), 2u);
}

TEST(ImageTexture, PictureIsUprightAndUnmirroredFromThePositiveSide) {
  // A 2 x 2 picture: top-left black, the rest white, on a vertical patch facing -x (normal -x).
  auto img = std::make_shared<ImageU8>(2, 2, 1, std::uint8_t{255});
  img->at(0, 0) = 0;
  Mat3 R;  // z = -x (towards the camera), y = up, x = y cross z
  R.col(2) = -Vec3::UnitX();
  R.col(1) = Vec3::UnitZ();
  R.col(0) = R.col(1).cross(R.col(2));
  World w;
  w.add(PlanePatch{SE3(R, Vec3(3.0, 0.0, 1.0)), 0.5, 0.5}, Surface{SemanticClass::kTargetObject, 1, 0.2, 1.0}, img);
  const auto cam = make_camera_model(pinhole(101, 101, 100.0));
  RenderOptions o;
  o.ambient = 1.0;  // no shading: intensity = 255 x reflectance
  const RenderedFrame f = render(w, *cam, camera_looking_at(Vec3(0.0, 0.0, 1.0), Vec3(3.0, 0.0, 1.0)), o);
  // The patch spans +-0.5 m at 3 m: +-16.7 px around the centre (50, 50). Top-left quarter dark.
  EXPECT_LT(f.intensity.at(42, 42), 30);
  EXPECT_GT(f.intensity.at(58, 42), 230);
  EXPECT_GT(f.intensity.at(42, 58), 230);
  EXPECT_GT(f.intensity.at(58, 58), 230);
  EXPECT_EQ(f.labels.at(50, 50), static_cast<std::uint8_t>(SemanticClass::kTargetObject));
  // Box filter: a pixel on the vertical black/white edge is grey.
  const int edge = f.intensity.at(50, 42);
  EXPECT_GT(edge, 60);
  EXPECT_LT(edge, 200);
}

TEST(LabWalkTarget, EveryLabWalkHasTheSameTaggedBoxOnTheSouthDesk) {
  for (int k = 1; k <= 5; ++k) {
    const Scenario s = make_scenario("lab-walk-" + std::to_string(k));
    const TargetObject& t = lab_target(s);
    EXPECT_EQ(t.semantic, SemanticClass::kTargetObject);
    EXPECT_EQ(t.tag_family, "36h11");
    EXPECT_EQ(t.tag_id, 5);
    EXPECT_NEAR(t.center_W.z() - t.half_extents.z(), 0.74, 1e-12);  // standing on the desk top
    // The tag sits on the box's face, its z axis pointing into the box.
    EXPECT_NEAR((t.T_W_tag.t - t.center_W).norm(), t.half_extents.x() + 0.002, 1e-9);
    EXPECT_GT(t.T_W_tag.rotation().col(2).dot(t.center_W - t.T_W_tag.t), 0.0);
    ASSERT_EQ(t.primitives.size(), 2u);
    for (std::uint32_t p : t.primitives) EXPECT_EQ(s.world.primitive(p).surface.semantic, SemanticClass::kTargetObject);
    EXPECT_NE(s.world.image_texture(t.primitives[1]), nullptr);
    // Added last: the lab's primitives come first.
    EXPECT_EQ(t.primitives[1] + 1, s.world.size());
  }
  for (const char* other : {"corridor", "route1", "office1"}) EXPECT_TRUE(make_scenario(other).targets.empty()) << other;
}

TEST(LabWalkTarget, LabelImageAndPrintedCodeBitsInARenderedFrame) {
  const Scenario s = make_scenario("lab-walk-1");
  const TargetObject& t = lab_target(s);
  const RayCaster rc(s.world);
  const auto cam = make_camera_model(pinhole(640, 480, 460.0));
  // From 1.8 m in front of the tag, 25 cm higher, looking at it.
  const Vec3 normal = -t.T_W_tag.rotation().col(2);
  const SE3 T_W_C = camera_looking_at(t.T_W_tag.t + 1.8 * normal + Vec3(0, 0, 0.25), t.T_W_tag.t);
  const RenderedFrame f = render(rc, *cam, T_W_C);
  const SE3 T_C_W = T_W_C.inverse();
  const auto centre = cam->project(T_C_W * t.T_W_tag.t);
  ASSERT_TRUE(centre);
  const int cu = static_cast<int>(std::lround(centre->x())), cv = static_cast<int>(std::lround(centre->y()));
  EXPECT_EQ(f.labels.at(cu, cv), static_cast<std::uint8_t>(SemanticClass::kTargetObject));
  std::size_t target_pixels = 0;
  for (auto l : f.labels.pixels) target_pixels += l == static_cast<std::uint8_t>(SemanticClass::kTargetObject);
  EXPECT_GT(target_pixels, 6000u);  // box face 34 cm at ~1.8 m: ~85 x 85 px
  EXPECT_NEAR(f.depth.at(cu, cv), (T_C_W * t.T_W_tag.t).z(), 0.01);

  // Every cell of the 10 x 10 pattern, read at its centre, is dark where the code says black.
  const ImageU8 cells = apriltag_cells("36h11", 5);
  const AprilTagFamilyInfo info = apriltag_family_info("36h11");
  const double cell = t.tag_size_m / info.width_at_border;
  int agree = 0, total = 0;
  for (int r = 0; r < cells.height; ++r)
    for (int c = 0; c < cells.width; ++c) {
      const Vec3 p_tag((c + 0.5 - 0.5 * cells.width) * cell, (r + 0.5 - 0.5 * cells.height) * cell, 0.0);
      const auto px = cam->project(T_C_W * (t.T_W_tag * p_tag));
      ASSERT_TRUE(px);
      const int v = f.intensity.at(static_cast<int>(std::lround(px->x())), static_cast<int>(std::lround(px->y())));
      const bool white = cells.at(c, r) > 127;
      agree += white ? v > 100 : v < 40;
      ++total;
    }
  EXPECT_EQ(agree, total);
}

TEST(LabWalkTarget, SimulateWritesTheTargetGroundTruth) {
  navaid::testing::ScratchDir dir("target_ground_truth");
  const Scenario s = make_scenario("lab-walk-1");
  const Config c = Config::parse("{}", "<test>", {"duration=0.3", "simulation.mode=features"});
  const SimulationConfig sc = read_simulation_config(c, s);
  simulate(s, sc, dir.path() / "rec");
  const auto targets = io::read_targets_csv(dir.path() / "rec" / io::kTargetsCsv);
  ASSERT_EQ(targets.size(), 1u);
  const TargetObject& t = lab_target(s);
  EXPECT_EQ(targets[0].name, t.name);
  EXPECT_EQ(targets[0].semantic, SemanticClass::kTargetObject);
  EXPECT_EQ(targets[0].tag_id, 5);
  EXPECT_EQ(targets[0].tag_size_m, t.tag_size_m);
  EXPECT_EQ(targets[0].center_W, t.center_W);
  EXPECT_EQ(targets[0].half_extents, t.half_extents);
  EXPECT_EQ(targets[0].T_W_tag.t, t.T_W_tag.t);
  EXPECT_LT(targets[0].T_W_tag.q.angularDistance(t.T_W_tag.q), 1e-12);

  // A scenario without targets writes none (and removes a stale file when overwriting).
  const Scenario corridor = make_scenario("corridor");
  const Config cc = Config::parse("{}", "<test>", {"duration=0.3", "simulation.mode=features"});
  SimulateOptions o;
  o.overwrite = true;
  simulate(corridor, read_simulation_config(cc, corridor), dir.path() / "rec", o);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "rec" / io::kTargetsCsv));
}

TEST(LabelConfusion, TargetObjectIsTakenForTheTableButNotTheOtherWayRound) {
  const LabelConfusionModel m;
  const auto t = static_cast<std::size_t>(SemanticClass::kTargetObject);
  const auto table = static_cast<std::size_t>(SemanticClass::kTable);
  EXPECT_NEAR(m.matrix()[t][t], 0.85, 1e-12);
  EXPECT_NEAR(m.matrix()[t][table], 0.15, 1e-12);
  EXPECT_EQ(m.matrix()[table][t], 0.0);
  // The table's row is what its two-way partners alone give: chair 2, bench 0.5.
  EXPECT_NEAR(m.matrix()[table][static_cast<std::size_t>(SemanticClass::kChair)], 0.2 * 2.0 / 2.5, 1e-12);
  LabelConfusionConfig bad;
  bad.one_way_confusions.push_back({SemanticClass::kTable, SemanticClass::kChair, 1.0});  // already two-way
  EXPECT_THROW(validate(bad), ConfigError);
  LabelConfusionConfig none;
  none.one_way_confusions.clear();  // target-object then has no partner for its error mass
  EXPECT_THROW(validate(none), ConfigError);
}

}  // namespace
}  // namespace navaid::simulation
