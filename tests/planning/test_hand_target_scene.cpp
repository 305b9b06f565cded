// The lab walks' tagged target box as the renderer draws it (image-textured plane patch) and the
// AprilTag detector sees it: id, centre and pose against the scenario's ground truth, from a few
// viewpoints in front of the box, with and without sensor-like intensity noise; and no tag from
// a viewpoint that looks away.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/planning/hand_guidance.hpp"
#include "navaid/simulation/rgbd_renderer.hpp"
#include "navaid/simulation/scenario.hpp"
#include "navaid/simulation/sensor_rig.hpp"

namespace navaid::planning {
namespace {

SE3 look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  const Vec3 x = z.cross(Vec3::UnitZ()).normalized();
  const Vec3 y = z.cross(x);
  Mat3 R;
  R << x, y, z;
  return SE3(R, eye);
}

class LabTarget : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scenario_ = new simulation::Scenario(simulation::make_scenario("lab-walk-2"));
    caster_ = new simulation::RayCaster(scenario_->world);
  }
  static void TearDownTestSuite() {
    delete caster_;
    delete scenario_;
  }
  static simulation::Scenario* scenario_;
  static simulation::RayCaster* caster_;
};
simulation::Scenario* LabTarget::scenario_ = nullptr;
simulation::RayCaster* LabTarget::caster_ = nullptr;

TEST_F(LabTarget, TheRenderedTagIsDetectedWithItsIdCentreAndPose) {
  ASSERT_EQ(scenario_->targets.size(), 1u);
  const simulation::TargetObject& t = scenario_->targets.front();
  const CameraCalibration calib = simulation::sensor_preset("structure-core").camera;
  const auto cam = make_camera_model(calib);
  AprilTagDetectorConfig dc;
  dc.tag_size_m = t.tag_size_m;
  AprilTagDetector detector(dc);
  const Vec3 normal = -t.T_W_tag.rotation().col(2);  // out of the printed face
  const Vec3 side = Vec3::UnitZ().cross(normal).normalized();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 2.0);
  struct View {
    double distance, lateral, height;
  };
  int checked = 0;
  for (const View v : {View{1.0, 0.0, 0.3}, View{2.0, 0.5, 0.35}, View{3.0, -0.8, 0.3}, View{4.0, 1.0, 0.32}}) {
    const Vec3 eye = t.T_W_tag.t + v.distance * normal + v.lateral * side + Vec3(0, 0, v.height);
    const SE3 T_W_C = look_at(eye, t.T_W_tag.t + 0.3 * side);  // the tag off the image centre
    simulation::RenderedFrame f = simulation::render(*caster_, *cam, T_W_C);
    for (auto& p : f.intensity.pixels) p = static_cast<std::uint8_t>(std::clamp(std::lround(p + noise(rng)), 0L, 255L));
    const auto tags = detector.detect(f.intensity, cam.get());
    const auto tag = find_tag(tags, t.tag_id);
    ASSERT_TRUE(tag) << "not detected from " << v.distance << " m";
    EXPECT_EQ(tags.size(), 1u);
    const SE3 T_C_W = T_W_C.inverse();
    const auto centre = cam->project(T_C_W * t.T_W_tag.t);
    ASSERT_TRUE(centre);
    EXPECT_LT((tag->centre_px - *centre).norm(), 0.5) << "from " << v.distance << " m";
    ASSERT_TRUE(tag->T_C_tag);
    EXPECT_LT((tag->T_C_tag->t - T_C_W * t.T_W_tag.t).norm(), 0.01 * v.distance) << "from " << v.distance << " m";
    // The depth patch at the centre lies on the printed card.
    const DepthPatchStats d = depth_patch_stats(f.depth, tag->centre_px, 5, 0.3, 5.0);
    EXPECT_EQ(d.valid, d.total);
    EXPECT_NEAR(d.median_m, (T_C_W * t.T_W_tag.t).z(), 0.01);
    ++checked;
  }
  EXPECT_EQ(checked, 4);
}

TEST_F(LabTarget, NoTagWhenLookingAway) {
  const simulation::TargetObject& t = scenario_->targets.front();
  const auto cam = make_camera_model(simulation::sensor_preset("structure-core").camera);
  AprilTagDetector detector;
  const Vec3 normal = -t.T_W_tag.rotation().col(2);
  const Vec3 eye = t.T_W_tag.t + 2.0 * normal + Vec3(0, 0, 0.3);
  const simulation::RenderedFrame f = simulation::render(*caster_, *cam, look_at(eye, eye + 2.0 * normal));
  EXPECT_TRUE(detector.detect(f.intensity).empty());
}

}  // namespace
}  // namespace navaid::planning
