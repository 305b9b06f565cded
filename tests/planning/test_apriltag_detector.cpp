// The AprilTag detector (ViSP's vpDetectorAprilTag behind a core-types header) on tag images
// drawn from the tag36h11 code words (simulation/apriltag_image.hpp): it finds the drawn id, its
// centre within a quarter pixel and its corners within half a pixel of where the camera model projects them, the tag's pose
// when given its size, and nothing on blank or noise images.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/planning/apriltag_detector.hpp"
#include "navaid/simulation/apriltag_image.hpp"
#include "navaid/simulation/sensor_rig.hpp"

namespace navaid::planning {
namespace {

std::unique_ptr<CameraModel> structure_core() {
  return make_camera_model(simulation::sensor_preset("structure-core").camera);
}

SE3 tag_pose(double roll_deg, double pitch_deg, double yaw_deg, const Vec3& t) {
  const double k = M_PI / 180.0;
  const Quat q = Quat(Eigen::AngleAxisd(yaw_deg * k, Vec3::UnitZ())) * Quat(Eigen::AngleAxisd(pitch_deg * k, Vec3::UnitY())) *
                 Quat(Eigen::AngleAxisd(roll_deg * k, Vec3::UnitX()));
  return SE3(q, t);
}

ImageU8 scene_with_tag(const CameraModel& cam, int id, const SE3& T_C_tag, double size_m, std::uint8_t background = 140) {
  ImageU8 img(cam.width(), cam.height(), 1, background);
  simulation::draw_apriltag(img, cam, T_C_tag, size_m, simulation::apriltag_cells("36h11", id), 8);
  return img;
}

TEST(AprilTagImage, CellsFollowTheFamilyLayout) {
  const simulation::AprilTagFamilyInfo info = simulation::apriltag_family_info("36h11");
  EXPECT_EQ(info.ncodes, 587);
  EXPECT_EQ(info.total_width, 10);
  EXPECT_EQ(info.width_at_border, 8);
  const ImageU8 a = simulation::apriltag_cells("36h11", 0);
  const ImageU8 b = simulation::apriltag_cells("36h11", 1);
  ASSERT_EQ(a.width, 10);
  for (int i = 0; i < 10; ++i) {  // white ring, black border
    EXPECT_EQ(a.at(i, 0), 255);
    EXPECT_EQ(a.at(0, i), 255);
    if (i >= 1 && i <= 8) {
      EXPECT_EQ(a.at(i, 1), 0);
      EXPECT_EQ(a.at(1, i), 0);
      EXPECT_EQ(a.at(i, 8), 0);
    }
  }
  EXPECT_FALSE(a == b);
  EXPECT_THROW(simulation::apriltag_cells("36h11", 587), Error);
  EXPECT_THROW(simulation::apriltag_cells("36h12", 0), Error);
}

TEST(AprilTagDetector, FindsTheDrawnIdAndCentreWithinAPixel) {
  const auto cam = structure_core();
  AprilTagDetector detector;
  struct Case {
    int id;
    SE3 T_C_tag;
  };
  const std::vector<Case> cases = {
      {0, tag_pose(0, 0, 0, Vec3(0.0, 0.0, 1.0))},
      {7, tag_pose(15, -20, 10, Vec3(0.12, -0.05, 0.9))},
      {123, tag_pose(-25, 10, -35, Vec3(-0.2, 0.1, 1.4))},
      {586, tag_pose(5, 30, 80, Vec3(0.05, 0.15, 0.7))},
  };
  for (const Case& c : cases) {
    const double size = 0.12;
    const ImageU8 img = scene_with_tag(*cam, c.id, c.T_C_tag, size);
    const std::vector<AprilTagDetection> found = detector.detect(img);
    ASSERT_EQ(found.size(), 1U) << "id " << c.id;
    EXPECT_EQ(found[0].id, c.id);
    const Eigen::Vector2d centre = *cam->project(c.T_C_tag * Vec3::Zero());
    EXPECT_LT((found[0].centre_px - centre).norm(), 0.25) << "id " << c.id << " centre " << found[0].centre_px.transpose()
                                                        << " expected " << centre.transpose();
    // Each detected corner lies within a pixel of one black-square corner.
    for (const Eigen::Vector2d& corner : found[0].corners_px) {
      double best = 1e9;
      for (const Vec3& p : {Vec3(-size / 2, -size / 2, 0), Vec3(size / 2, -size / 2, 0), Vec3(size / 2, size / 2, 0),
                           Vec3(-size / 2, size / 2, 0)}) {
        best = std::min(best, (*cam->project(c.T_C_tag * p) - corner).norm());
      }
      EXPECT_LT(best, 0.5) << "id " << c.id << " corner " << corner.transpose();
    }
  }
}

TEST(AprilTagDetector, SeveralTagsSortedByIdAndFindTag) {
  const auto cam = structure_core();
  ImageU8 img(cam->width(), cam->height(), 1, 150);
  simulation::draw_apriltag(img, *cam, tag_pose(0, 0, 0, Vec3(-0.3, 0.0, 1.2)), 0.12, simulation::apriltag_cells("36h11", 42), 8);
  simulation::draw_apriltag(img, *cam, tag_pose(0, 10, 0, Vec3(0.3, 0.05, 1.2)), 0.12, simulation::apriltag_cells("36h11", 5), 8);
  AprilTagDetector detector;
  const auto found = detector.detect(img);
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0].id, 5);
  EXPECT_EQ(found[1].id, 42);
  ASSERT_TRUE(find_tag(found, 42).has_value());
  EXPECT_GT(find_tag(found, 42)->centre_px.x(), cam->cx() - 200.0);
  EXPECT_LT(find_tag(found, 42)->centre_px.x(), cam->cx());
  EXPECT_FALSE(find_tag(found, 6).has_value());
}

TEST(AprilTagDetector, PoseFromTheTagSize) {
  const auto cam = structure_core();
  AprilTagDetectorConfig config;
  config.tag_size_m = 0.12;
  AprilTagDetector detector(config);
  const SE3 truth = tag_pose(10, -15, 20, Vec3(0.08, -0.04, 1.1));
  const auto found = detector.detect(scene_with_tag(*cam, 3, truth, 0.12), cam.get());
  ASSERT_EQ(found.size(), 1U);
  ASSERT_TRUE(found[0].T_C_tag.has_value());
  EXPECT_LT((found[0].T_C_tag->t - truth.t).norm(), 0.005) << found[0].T_C_tag->t.transpose();
  EXPECT_LT(found[0].T_C_tag->q.angularDistance(truth.q), 2.0 * M_PI / 180.0);
}

TEST(AprilTagDetector, NothingOnBlankOrNoiseImages) {
  AprilTagDetector detector;
  EXPECT_TRUE(detector.detect(ImageU8(640, 480, 1, 0)).empty());
  EXPECT_TRUE(detector.detect(ImageU8(640, 480, 1, 255)).empty());
  ImageU8 noise(640, 480, 1, 0);
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> value(0, 255);
  for (auto& p : noise.pixels) p = static_cast<std::uint8_t>(value(rng));
  EXPECT_TRUE(detector.detect(noise).empty());
  EXPECT_TRUE(detector.detect(ImageU8()).empty());
  EXPECT_THROW(detector.detect(ImageU8(64, 48, 3, 0)), Error);
}

TEST(AprilTagDetector, ConfigKeysAreRangeChecked) {
  const AprilTagDetectorConfig c = read_apriltag_detector_config(
      Config::parse("planning:\n  apriltag:\n    quad_decimate: 2\n    threads: 2\n    tag_size_m: 0.1\n"));
  EXPECT_DOUBLE_EQ(c.quad_decimate, 2.0);
  EXPECT_EQ(c.threads, 2);
  EXPECT_DOUBLE_EQ(c.tag_size_m, 0.1);
  EXPECT_THROW(read_apriltag_detector_config(Config::parse("planning:\n  apriltag:\n    family: 99h1\n")), ConfigError);
  EXPECT_THROW(read_apriltag_detector_config(Config::parse("planning:\n  apriltag:\n    quad_decimate: 0.5\n")), ConfigError);
}

}  // namespace
}  // namespace navaid::planning
