// End-to-end: a simulated rendered walk written as a ROS bag by python3-rosbag
// (tests/apps/fixtures/recording_to_bag.py), then navaid info / convert / run on the bag.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class RosBagCli : public ::testing::Test {
 protected:
  // 6 s of the corridor at 320x240, 15 Hz; the same walk as a bz2 and as an lz4 bag.
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("ros_bag_cli");
    const auto sim = navaid_cli("simulate --scenario corridor --mount cane --seed 3 --threads 1 --out '" +
                                path("walk").string() +
                                "' --set duration=6 --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=15");
    ASSERT_EQ(sim.status, 0) << sim.output;
    for (const char* compression : {"bz2", "lz4"}) {
      const std::string command = "/usr/bin/python3 '" + std::string(NAVAID_SOURCE_DIR) +
                                  "/tests/apps/fixtures/recording_to_bag.py' '" + path("walk").string() + "' '" +
                                  path(std::string("walk-") + compression + ".bag").string() + "' --compression " +
                                  compression;
      ASSERT_EQ(std::system(command.c_str()), 0) << command;
    }
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
  static std::unique_ptr<ScratchDir> dir_;
};
std::unique_ptr<ScratchDir> RosBagCli::dir_;

// The simulator's depth model (0.4-6 m, 95 mm baseline, 0.08 px) given to the bag run, so both runs
// see the same calibration: the estimates are the same bytes.
TEST_F(RosBagCli, RunOnTheBagGivesTheRecordingsEstimates) {
  const auto on_recording = navaid_cli("run --recording " + q(path("walk")) + " --out " + q(path("run-rec")) + " --no-plot");
  ASSERT_EQ(on_recording.status, 0) << on_recording.output;
  const auto on_bag = navaid_cli("run --recording " + q(path("walk-bz2.bag")) + " --out " + q(path("run-bag")) +
                                 " --bag-preset realsense --imu-noise " + q(path("walk-bz2.bag.imu.yaml")) +
                                 " --depth-range 0.4 6 --set estimator.depth.baseline=0.095"
                                 " --set estimator.depth.disparity_sigma=0.08 --no-plot");
  ASSERT_EQ(on_bag.status, 0) << on_bag.output;
  EXPECT_NE(on_bag.output.find("RGBD-VIO"), std::string::npos) << on_bag.output;
  EXPECT_TRUE(fs::exists(path("run-bag") / "recording" / "recording.yaml"));  // converted once, kept
  EXPECT_EQ(read_text(path("run-bag") / "trajectory.tum"), read_text(path("run-rec") / "trajectory.tum"));
  EXPECT_EQ(read_text(path("run-bag") / "estimates.csv"), read_text(path("run-rec") / "estimates.csv"));

  // A D455 preset gives the datasheet's range and baseline: depth is used.
  const auto preset = navaid_cli("run --recording " + q(path("walk-bz2.bag")) + " --out " + q(path("run-d455")) +
                                 " --bag-preset realsense-d455 --imu-noise " + q(path("walk-bz2.bag.imu.yaml")) +
                                 " --no-plot");
  ASSERT_EQ(preset.status, 0) << preset.output;
  EXPECT_EQ(preset.output.find(" 0 % RGBD-VIO"), std::string::npos) << preset.output;
}

TEST_F(RosBagCli, InfoAndConvertOnBothCompressions) {
  const auto info = navaid_cli("info " + q(path("walk-lz4.bag")));
  ASSERT_EQ(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("/camera/aligned_depth_to_color/image_raw"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("sensor_msgs/CameraInfo"), std::string::npos) << info.output;
  for (const char* c : {"bz2", "lz4"}) {
    const fs::path out = path(std::string("converted-") + c);
    const auto run = navaid_cli("convert " + q(path(std::string("walk-") + c + ".bag")) + " " + q(out) +
                                " --bag-preset realsense-d455 --imu-noise " + q(path("walk-bz2.bag.imu.yaml")));
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("91 frames"), std::string::npos) << run.output;
  }
  // The same messages in either compression: the same recording, byte for byte.
  EXPECT_EQ(navaid::testing::folder_contents(path("converted-bz2")),
            navaid::testing::folder_contents(path("converted-lz4")));
  // Frames and IMU as in the simulated recording.
  EXPECT_EQ(read_text(path("converted-bz2") / "imu.csv"), read_text(path("walk") / "imu.csv"));
  EXPECT_EQ(read_text(path("converted-bz2") / "rgb" / "cam0_1704067199000000000.png").size(),
            read_text(path("walk") / "rgb" / "cam0_1704067199000000000.png").size());
}

TEST_F(RosBagCli, BadBagOptionsAreClearErrors) {
  const fs::path bag = path("walk-bz2.bag");
  auto r = navaid_cli("run --recording " + q(bag) + " --out " + q(path("no-noise")) + " --no-plot");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--imu-noise"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(bag) + " " + q(path("bad-role")) + " --topic lidar=/points");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("unknown role"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(bag) + " " + q(path("bad-topic")) + " --topic /camera/imu");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("ROLE=TOPIC"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(bag) + " " + q(path("missing-topic")) + " --topic imu=/imu/data");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("/imu/data (named for imu) is not in the bag"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(bag) + " " + q(path("bad-preset")) + " --bag-preset kinect");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("unknown preset 'kinect'"), std::string::npos) << r.output;
  r = navaid_cli("run --recording " + q(path("walk")) + " --out " + q(path("not-a-bag")) + " --bag-preset realsense");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("need a bag as --recording"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(path("walk")) + " " + q(path("not-a-bag2")) + " --topic imu=/x");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("are for ROS bags"), std::string::npos) << r.output;
  r = navaid_cli("map --recording " + q(bag) + " --poses groundtruth --out " + q(path("map")));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("convert it into a navaid recording first"), std::string::npos) << r.output;
}

}  // namespace
