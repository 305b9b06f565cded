// End-to-end tests of `navaid run` on image recordings: a rendered walk through the image front end
// and the sliding-window estimator, its run folder, replay determinism, VIO without depth images,
// and the errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "navaid/io/navaid_recording.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class RunImagesCli : public ::testing::Test {
 protected:
  // One rendered walk for the suite: 8 s of lab-walk-1 (1 s still start), hand mount, 320x240 at
  // 15 Hz to keep it quick (once for all the suite's test processes).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("run_images_cli");
    inputs_ = navaid::testing::shared_cli_fixture(
        "images-walk", {"simulate --scenario lab-walk-1 --mount hand --seed 5 --threads 1 --out {dir}/walk"
                        " --set duration=8 --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=15"});
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static fs::path recording() { return inputs_ / "walk"; }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static navaid::testing::CliRun run(const fs::path& rec, const fs::path& out, const std::string& extra = {}) {
    return navaid_cli("run --recording '" + rec.string() + "' --out '" + out.string() + "'" + extra);
  }

  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};

std::unique_ptr<ScratchDir> RunImagesCli::dir_;
fs::path RunImagesCli::inputs_;

TEST_F(RunImagesCli, TracksTheImagesAndEstimatesTheWalk) {
  const fs::path out = path("run");
  const auto result = run(recording(), out);
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("from images"), std::string::npos) << result.output;

  const auto rec = navaid::io::read_navaid_recording(recording());
  ASSERT_TRUE(rec.features.empty());
  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["input"], "images (front end)");
  EXPECT_EQ(summary["frames"].get<std::size_t>(), rec.frames.size());
  EXPECT_EQ(summary["frontend"]["frames_tracked"].get<std::size_t>(), rec.frames.size());
  EXPECT_GT(summary["mode_fractions"]["rgbd-vio"].get<double>(), 0.8);
  EXPECT_EQ(summary["mode_fractions"]["lost"].get<double>(), 0.0);
  const auto& t = summary["time_per_frame_ms"];
  EXPECT_GT(t["frontend_median"].get<double>(), 0.0);
  EXPECT_GE(t["median"].get<double>(), t["frontend_median"].get<double>() * 0.5);

  // The walk is estimated: a loose bound (measured 0.27 % of the 7.4 m path).
  ASSERT_TRUE(summary.contains("ate"));
  EXPECT_GT(summary["ate"]["path_length_m"].get<double>(), 5.0);
  EXPECT_LT(summary["ate"]["percent_of_path"].get<double>(), 2.0);
  const auto trajectory = navaid::io::read_tum_trajectory(out / "trajectory.tum");
  EXPECT_GT(trajectory.size(), rec.frames.size() * 8 / 10);

  // timing.csv: one row per frame with the front end's share of it and the estimator's stages.
  std::istringstream timing(read_text(out / "timing.csv"));
  std::string line;
  std::getline(timing, line);
  EXPECT_EQ(line, "t_ns,ms,mode,frontend_ms,image_load_ms,keyframe,solve_ms,covariance_ms,marginalization_ms");
  std::size_t rows = 0, keyframes = 0, marginalizations = 0;
  while (std::getline(timing, line)) {
    ++rows;
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 9u) << line;
    EXPECT_GT(std::stod(cells[3]), 0.0) << line;  // the front end tracked every frame
    if (cells[2] == "initializing") continue;
    EXPECT_GT(std::stod(cells[6]), 0.0) << line;  // every estimated frame was solved
    EXPECT_GT(std::stod(cells[7]), 0.0) << line;  // with its covariance
    keyframes += cells[5] == "1";
    marginalizations += std::stod(cells[8]) > 0.0;
    if (cells[5] == "0") {
      EXPECT_EQ(std::stod(cells[8]), 0.0) << line;
    }
  }
  EXPECT_EQ(rows, rec.frames.size());
  EXPECT_GT(keyframes, 0u);
  EXPECT_GT(marginalizations, 0u);

  // Replay is deterministic: a second run (which also saves its front end's tracks) writes the
  // same estimates bit for bit.
  const fs::path again = path("run-again");
  const fs::path tracks = path("tracks");
  ASSERT_EQ(run(recording(), again, " --save-features '" + tracks.string() + "'").status, 0);
  EXPECT_EQ(read_text(out / "trajectory.tum"), read_text(again / "trajectory.tum"));
  EXPECT_EQ(read_text(out / "estimates.csv"), read_text(again / "estimates.csv"));

  // The front end / back end split is exact: the saved tracks, a feature-level recording, run
  // through the back end alone give the image run's estimates bit for bit.
  const auto saved = navaid::io::read_navaid_recording(tracks);
  EXPECT_TRUE(saved.frames.empty());
  EXPECT_EQ(saved.features.size(), rec.frames.size());
  EXPECT_EQ(saved.imu.size(), rec.imu.size());
  const fs::path back_end = path("run-tracks");
  const auto on_tracks = run(tracks, back_end);
  ASSERT_EQ(on_tracks.status, 0) << on_tracks.output;
  EXPECT_EQ(nlohmann::json::parse(read_text(back_end / "summary.json"))["input"], "features");
  EXPECT_EQ(read_text(out / "estimates.csv"), read_text(back_end / "estimates.csv"));
}

TEST_F(RunImagesCli, TheDriftCheckMakesTheCovarianceMoreHonest) {
  // The front end's drift check (frontend.drift_check_interval, default 3 frames) against
  // frame-to-frame KLT alone, on the same images: the position NEES falls towards 3 (measured on
  // this walk: 13.9 without, 8.4 with; docs/estimator.md, "Front end or back end").
  const fs::path with = path("drift-check"), without = path("no-drift-check");
  ASSERT_EQ(run(recording(), with).status, 0);
  ASSERT_EQ(run(recording(), without, " --set frontend.drift_check_interval=0").status, 0);
  const auto a = nlohmann::json::parse(read_text(with / "summary.json"));
  const auto b = nlohmann::json::parse(read_text(without / "summary.json"));
  const auto& drift = a["frontend"]["drift_check"];
  EXPECT_GT(drift["checked"].get<std::size_t>(), 1000u);
  EXPECT_GT(drift["corrected"].get<std::size_t>(), drift["checked"].get<std::size_t>() / 2);
  EXPECT_GT(drift["dropped"].get<std::size_t>(), 0u);
  EXPECT_EQ(b["frontend"]["drift_check"]["checked"].get<std::size_t>(), 0u);
  const double nees_with = a["nees"]["position_mean"].get<double>();
  const double nees_without = b["nees"]["position_mean"].get<double>();
  EXPECT_LT(nees_with, 0.75 * nees_without) << nees_with << " vs " << nees_without;
  RecordProperty("position_nees_x100_with_without",
                 std::to_string(std::lround(nees_with * 100)) + "/" + std::to_string(std::lround(nees_without * 100)));
}

TEST_F(RunImagesCli, WithoutDepthImagesItRunsAsVio) {
  navaid::io::Recording rec = navaid::io::read_navaid_recording(recording());
  for (auto& f : rec.frames) {
    f.depth_path.clear();
    f.labels_path.clear();  // not needed by the estimator; saves re-encoding them
    f.confidence_path.clear();
  }
  const fs::path no_depth = path("no-depth");
  navaid::io::write_navaid_recording(rec, no_depth);

  const fs::path out = path("run-vio");
  const auto result = run(no_depth, out);
  ASSERT_EQ(result.status, 0) << result.output;
  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_FALSE(summary["depth"].get<bool>());
  EXPECT_EQ(summary["mode_fractions"]["rgbd-vio"].get<double>(), 0.0);
  // Measured 82 % VIO; the rest is the still start (initializing, then imu-only until the walk
  // gives the parallax to triangulate: no depth to start from).
  EXPECT_GT(summary["mode_fractions"]["vio"].get<double>(), 0.7);
  EXPECT_EQ(summary["mode_fractions"]["lost"].get<double>(), 0.0);
  EXPECT_NE(read_text(out / "estimates.csv").find(",vio,"), std::string::npos);
  ASSERT_TRUE(summary.contains("ate"));
  EXPECT_LT(summary["ate"]["percent_of_path"].get<double>(), 2.0);  // measured 0.32 %
}

TEST_F(RunImagesCli, ClearErrors) {
  // Front-end keys go through --set and are validated with the key named.
  const auto bad = run(recording(), path("bad"), " --set frontend.klt_window_px=4");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("frontend.klt_window_px"), std::string::npos) << bad.output;
  const auto typo = run(recording(), path("bad"), " --set frontend.max_feature=100");
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("frontend.max_feature"), std::string::npos) << typo.output;

  navaid::io::Recording rec = navaid::io::read_navaid_recording(recording());
  // Neither features nor frames: nothing to see.
  navaid::io::Recording imu_only = rec;
  imu_only.frames.clear();
  navaid::io::write_navaid_recording(imu_only, path("imu-only"));
  const auto none = run(path("imu-only"), path("bad"));
  EXPECT_NE(none.status, 0);
  EXPECT_NE(none.output.find("no camera data"), std::string::npos) << none.output;

  // Frames of a camera the calibration's first camera is not.
  navaid::io::Recording other = rec;
  other.frames.resize(3);
  for (auto& f : other.frames) {
    f.camera = "cam9";
    f.labels_path.clear();
    f.confidence_path.clear();
  }
  navaid::io::write_navaid_recording(other, path("other-camera"));
  const auto wrong_camera = run(path("other-camera"), path("bad"));
  EXPECT_NE(wrong_camera.status, 0);
  EXPECT_NE(wrong_camera.output.find("no image frames of camera"), std::string::npos) << wrong_camera.output;

  // Tracks are saved from images only, into a folder of their own.
  navaid::io::Recording features_only = rec;
  features_only.frames.clear();
  features_only.features = {navaid::FeatureFrame{rec.frames.front().t, "cam0", {}}};
  navaid::io::write_navaid_recording(features_only, path("features-only"));
  const auto from_features = run(path("features-only"), path("bad"), " --save-features '" + path("t1").string() + "'");
  EXPECT_NE(from_features.status, 0);
  EXPECT_NE(from_features.output.find("feature-level already"), std::string::npos) << from_features.output;
  navaid::testing::write_text(path("taken") / "note.txt", "mine");
  const auto taken = run(recording(), path("bad"), " --save-features '" + path("taken").string() + "'");
  EXPECT_NE(taken.status, 0);
  EXPECT_NE(taken.output.find("holds files already"), std::string::npos) << taken.output;

  // A trajectory file is not a recording.
  const auto not_recording = run(recording() / "groundtruth.tum", path("bad"));
  EXPECT_NE(not_recording.status, 0);
  EXPECT_NE(not_recording.output.find("not a recording with IMU and camera data"), std::string::npos)
      << not_recording.output;
}

}  // namespace
