// End-to-end: a simulated rendered walk written as a ROS bag by python3-rosbag
// (tests/apps/fixtures/recording_to_bag.py), then navaid info / convert / run on the bag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "navaid/io/text_file.hpp"

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class RosBagCli : public ::testing::Test {
 protected:
  // 6 s of the corridor at 320x240, 15 Hz; the same walk as a bz2 and as an lz4 bag (made once for
  // all the suite's test processes).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("ros_bag_cli");
    const std::string simulate =
        "simulate --scenario corridor --mount cane --seed 3 --threads 1 --set duration=6"
        " --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=15 --out ";
    const std::string to_bag = "/usr/bin/python3 '" + std::string(NAVAID_SOURCE_DIR) +
                               "/tests/apps/fixtures/recording_to_bag.py' ";
    inputs_ = navaid::testing::shared_fixture("ros-bag-walk", simulate + "\n" + to_bag, [&](const fs::path& folder) {
      const auto sim = navaid_cli(simulate + q(folder / "walk"));
      if (sim.status != 0) throw std::runtime_error(sim.output);
      for (const char* compression : {"bz2", "lz4"}) {
        const std::string command = to_bag + q(folder / "walk") + " " +
                                    q(folder / (std::string("walk-") + compression + ".bag")) + " --compression " +
                                    compression;
        if (std::system(command.c_str()) != 0) throw std::runtime_error(command + " failed");
      }
    });
  }
  static void TearDownTestSuite() { dir_.reset(); }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static fs::path input(const std::string& name) { return inputs_ / name; }
  static std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};
std::unique_ptr<ScratchDir> RosBagCli::dir_;
fs::path RosBagCli::inputs_;

// The simulator's depth model (0.4-6 m, 95 mm baseline, 0.08 px) given to the bag run, so both runs
// see the same calibration: the estimates are the same bytes.
TEST_F(RosBagCli, RunOnTheBagGivesTheRecordingsEstimates) {
  const auto on_recording = navaid_cli("run --recording " + q(input("walk")) + " --out " + q(path("run-rec")) + " --no-plot");
  ASSERT_EQ(on_recording.status, 0) << on_recording.output;
  const auto on_bag = navaid_cli("run --recording " + q(input("walk-bz2.bag")) + " --out " + q(path("run-bag")) +
                                 " --bag-preset realsense --imu-noise " + q(input("walk-bz2.bag.imu.yaml")) +
                                 " --depth-range 0.4 6 --set estimator.depth.baseline=0.095"
                                 " --set estimator.depth.disparity_sigma=0.08 --no-plot");
  ASSERT_EQ(on_bag.status, 0) << on_bag.output;
  EXPECT_NE(on_bag.output.find("RGBD-VIO"), std::string::npos) << on_bag.output;
  EXPECT_TRUE(fs::exists(path("run-bag") / "recording" / "recording.yaml"));  // converted once, kept
  EXPECT_EQ(read_text(path("run-bag") / "trajectory.tum"), read_text(path("run-rec") / "trajectory.tum"));
  EXPECT_EQ(read_text(path("run-bag") / "estimates.csv"), read_text(path("run-rec") / "estimates.csv"));

  // A D455 preset gives the datasheet's range and baseline: depth is used.
  const auto preset = navaid_cli("run --recording " + q(input("walk-bz2.bag")) + " --out " + q(path("run-d455")) +
                                 " --bag-preset realsense-d455 --imu-noise " + q(input("walk-bz2.bag.imu.yaml")) +
                                 " --no-plot");
  ASSERT_EQ(preset.status, 0) << preset.output;
  EXPECT_EQ(preset.output.find(" 0 % RGBD-VIO"), std::string::npos) << preset.output;
}

TEST_F(RosBagCli, InfoAndConvertOnBothCompressions) {
  const auto info = navaid_cli("info " + q(input("walk-lz4.bag")));
  ASSERT_EQ(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("/camera/aligned_depth_to_color/image_raw"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("sensor_msgs/CameraInfo"), std::string::npos) << info.output;
  for (const char* c : {"bz2", "lz4"}) {
    const fs::path out = path(std::string("converted-") + c);
    const auto run = navaid_cli("convert " + q(input(std::string("walk-") + c + ".bag")) + " " + q(out) +
                                " --bag-preset realsense-d455 --imu-noise " + q(input("walk-bz2.bag.imu.yaml")));
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("91 frames"), std::string::npos) << run.output;
  }
  // The same messages in either compression: the same recording, byte for byte.
  EXPECT_EQ(navaid::testing::folder_contents(path("converted-bz2")),
            navaid::testing::folder_contents(path("converted-lz4")));
  // Frames and IMU as in the simulated recording.
  EXPECT_EQ(read_text(path("converted-bz2") / "imu.csv"), read_text(input("walk") / "imu.csv"));
  EXPECT_EQ(read_text(path("converted-bz2") / "rgb" / "cam0_1704067199000000000.png").size(),
            read_text(input("walk") / "rgb" / "cam0_1704067199000000000.png").size());
}

TEST_F(RosBagCli, BadBagOptionsAreClearErrors) {
  const fs::path bag = input("walk-bz2.bag");
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
  r = navaid_cli("run --recording " + q(input("walk")) + " --out " + q(path("not-a-bag")) + " --bag-preset realsense");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("need a bag as --recording"), std::string::npos) << r.output;
  r = navaid_cli("convert " + q(input("walk")) + " " + q(path("not-a-bag2")) + " --topic imu=/x");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("are for ROS bags"), std::string::npos) << r.output;
  r = navaid_cli("map --recording " + q(bag) + " --poses groundtruth --out " + q(path("map")));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("convert it into a navaid recording first"), std::string::npos) << r.output;
}

}  // namespace

namespace {

// What python3-rosbag reads back from a bag (tests/apps/fixtures/bag_contents.py).
nlohmann::json bag_contents(const fs::path& bag) {
  const std::string command =
      "/usr/bin/python3 '" + std::string(NAVAID_SOURCE_DIR) + "/tests/apps/fixtures/bag_contents.py' '" + bag.string() + "'";
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {};
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  if (pclose(pipe) != 0) return {};
  return nlohmann::json::parse(out);
}

std::size_t count_lines(const fs::path& file) {
  const std::string text = read_text(file);
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::vector<std::string> lines;
  std::istringstream in(read_text(file));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A full-device run (Smart Cane: map, plans, cues) exported for RViz and read back by python3-rosbag.
TEST_F(RosBagCli, ExportWritesTheRunForRViz) {
  const fs::path run = path("device-run");
  const auto r = navaid_cli("run --recording " + q(input("walk")) + " --out " + q(run) + " --device smart-cane --no-plot");
  ASSERT_EQ(r.status, 0) << r.output;
  const fs::path bag = path("device-run.bag");
  const auto e = navaid_cli("export --run " + q(run) + " --bag " + q(bag));
  ASSERT_EQ(e.status, 0) << e.output;
  const auto c = bag_contents(bag);
  ASSERT_TRUE(c.contains("topics")) << e.output;
  const std::size_t estimates = count_lines(run / "estimates.csv") - 1;
  EXPECT_EQ(c["topics"]["/tf"]["count"], estimates);
  EXPECT_EQ(c["topics"]["/tf"]["type"], "tf2_msgs/TFMessage");
  EXPECT_EQ(c["topics"]["/navaid/pose"]["count"], estimates);
  EXPECT_EQ(c["topics"]["/navaid/pose"]["type"], "geometry_msgs/PoseWithCovarianceStamped");
  EXPECT_EQ(c["topics"]["/tf_static"]["count"], 1);
  EXPECT_EQ(c["topics"]["/navaid/path"]["type"], "nav_msgs/Path");
  EXPECT_GE(c["topics"]["/navaid/path"]["count"].get<int>(), 6);  // 1 Hz over 6 s, and the end
  EXPECT_EQ(c["last_path_poses"], estimates);
  EXPECT_EQ(c["topics"]["/navaid/map"]["type"], "sensor_msgs/PointCloud2");
  EXPECT_EQ(c["topics"]["/navaid/markers"]["type"], "visualization_msgs/MarkerArray");
  for (const char* topic : {"/tf", "/navaid/pose", "/navaid/path", "/navaid/map", "/navaid/markers"})
    EXPECT_EQ(c["topics"][topic]["frame_ids"], nlohmann::json::array({"world"})) << topic;
  EXPECT_EQ(c["transforms"], nlohmann::json::parse(R"([["body", "camera"], ["world", "body"]])"));
  // body -> camera is the recording's T_B_C.
  const auto calibration = read_text(input("walk") / "calibration.yaml");
  const auto q_bc = c["tf_static"][0];
  EXPECT_NE(calibration.find(nlohmann::json(q_bc[0]).dump()), std::string::npos) << q_bc << calibration;
  // The last pose's covariance: position block as estimated, rotation block turned from body axes
  // (ours, on the right) to the world's fixed axes (ROS's): R Sigma R^T.
  const auto last = navaid::io::split_fields(lines_of(run / "estimates.csv").back(), ',');
  const auto num = [&](std::size_t i) { return std::stod(std::string(last[i])); };
  const Eigen::Quaterniond q_wb(num(4), num(5), num(6), num(7));
  Eigen::Matrix3d sigma_p, sigma_r;
  sigma_p << num(18), num(19), num(20), num(19), num(21), num(22), num(20), num(22), num(23);  // cov_pxx ...
  sigma_r << num(24), num(25), num(26), num(25), num(27), num(28), num(26), num(28), num(29);  // cov_rxx ...
  const Eigen::Matrix3d expected_r = q_wb.toRotationMatrix() * sigma_r * q_wb.toRotationMatrix().transpose();
  const auto cov = c["last_pose"]["covariance"];
  for (int row = 0; row < 3; ++row)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(cov[6 * row + k].get<double>(), sigma_p(row, k), 1e-12 + 1e-9 * std::abs(sigma_p(row, k)));
      EXPECT_NEAR(cov[6 * (row + 3) + k + 3].get<double>(), expected_r(row, k),
                  1e-12 + 1e-9 * std::abs(expected_r(row, k)));
      EXPECT_EQ(cov[6 * row + k + 3].get<double>(), 0.0);  // estimates.csv keeps no cross terms
    }
  EXPECT_GT(sigma_r(0, 0), 0.0);
  EXPECT_FALSE(expected_r.isApprox(sigma_r, 1e-3));  // the turn matters: the test can fail
  // The map cloud holds every vertex of map.ply, with its class colour and id.
  const std::string ply = read_text(run / "map" / "map.ply");
  const auto vertices = std::stoul(ply.substr(ply.find("element vertex ") + 15));
  EXPECT_EQ(c["map"]["width"], vertices);
  EXPECT_EQ(c["map"]["fields"], nlohmann::json::parse(R"(["x","y","z","rgb","class_id","probability","occupancy"])"));
  for (const char* ns : {"obstacles", "plan", "cue", "cue_text"})
    EXPECT_NE(std::find(c["marker_namespaces"].begin(), c["marker_namespaces"].end(), ns), c["marker_namespaces"].end())
        << ns;

  // The RViz configuration in docs/ shows every topic the export writes.
  const std::string rviz = read_text(fs::path(NAVAID_SOURCE_DIR) / "docs" / "navaid.rviz");
  for (const auto& entry : c["topics"].items()) {
    const std::string& topic = entry.key();
    if (topic == "/tf" || topic == "/tf_static") continue;  // TF needs no display topic
    EXPECT_NE(rviz.find(topic), std::string::npos) << topic;
  }
  EXPECT_NE(rviz.find("Fixed Frame: world"), std::string::npos);

  // Bad input: not a run folder, an unknown compression, a recording that is gone.
  auto bad = navaid_cli("export --run " + q(input("walk")) + " --bag " + q(path("x.bag")));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("estimates.csv"), std::string::npos) << bad.output;
  bad = navaid_cli("export --run " + q(run) + " --bag " + q(path("x.bag")) + " --compression zstd");
  EXPECT_NE(bad.status, 0);
  bad = navaid_cli("export --run " + q(run) + " --bag " + q(path("x.bag")) + " --recording " + q(path("gone")));
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("gone"), std::string::npos) << bad.output;
}

}  // namespace
