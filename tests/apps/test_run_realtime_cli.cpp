// End-to-end tests of `navaid run --realtime` (front end and estimator on their own threads) and
// of the run's top-view figure: with nothing dropped the estimates equal replay's byte for byte,
// paced runs account for every frame, and a figure that cannot be drawn does not fail the run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;

namespace {

class RunRealtimeCli : public ::testing::Test {
 protected:
  // 5 s of lab-walk-1 (1 s still start), hand mount, rendered at 320x240 and 15 Hz to keep it quick
  // (once for all the suite's test processes).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<ScratchDir>("run_realtime_cli");
    inputs_ = navaid::testing::shared_cli_fixture(
        "realtime-walk", {"simulate --scenario lab-walk-1 --mount hand --seed 3 --threads 1 --out {dir}/walk"
                          " --set duration=5 --set sensor.camera.resolution=[320,240] --set sensor.camera.rate=15"});
  }
  static void TearDownTestSuite() { dir_.reset(); }

  static fs::path images() { return inputs_ / "walk"; }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static navaid::testing::CliRun run(const fs::path& rec, const fs::path& out, const std::string& extra = {}) {
    return navaid_cli("run --recording '" + rec.string() + "' --out '" + out.string() + "'" + extra);
  }
  static nlohmann::json summary(const fs::path& out) { return nlohmann::json::parse(read_text(out / "summary.json")); }

  static std::unique_ptr<ScratchDir> dir_;
  static fs::path inputs_;
};

std::unique_ptr<ScratchDir> RunRealtimeCli::dir_;
fs::path RunRealtimeCli::inputs_;

std::size_t data_rows(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::size_t rows = 0;
  std::getline(in, line);
  while (std::getline(in, line)) rows += !line.empty();
  return rows;
}

TEST_F(RunRealtimeCli, AsFastAsPossibleItEqualsReplayByteForByte) {
  const auto replay = run(images(), path("replay"), " --no-plot");
  ASSERT_EQ(replay.status, 0) << replay.output;
  // Default front end: the KLT prediction needs the back end's gyro bias, so the front end
  // waits for it (replay's data flow) and only image loading overlaps.
  const auto rt = run(images(), path("rt"), " --no-plot --realtime");
  ASSERT_EQ(rt.status, 0) << rt.output;
  EXPECT_EQ(read_text(path("replay") / "trajectory.tum"), read_text(path("rt") / "trajectory.tum"));
  EXPECT_EQ(read_text(path("replay") / "estimates.csv"), read_text(path("rt") / "estimates.csv"));

  const auto s = summary(path("rt"));
  EXPECT_EQ(s["pipeline"]["mode"], "realtime");
  EXPECT_EQ(summary(path("replay"))["pipeline"]["mode"], "replay");
  const auto& r = s["realtime"];
  EXPECT_EQ(r["frames_dropped"].get<std::size_t>(), 0u);
  EXPECT_EQ(r["frontend_thread"]["frames_handed_over"], r["frontend_thread"]["frames_in"]);
  EXPECT_EQ(r["frontend_thread"]["frames_in"].get<std::size_t>(), s["frames"].get<std::size_t>());
  EXPECT_LE(r["queue_max_depth"].get<std::size_t>(), r["queue_capacity"].get<std::size_t>());
  EXPECT_GT(r["estimator_thread"]["busy_s"].get<double>(), 0.0);

  // timing.csv gains the estimator thread's share and the latency.
  const std::string timing = read_text(path("rt") / "timing.csv");
  EXPECT_EQ(timing.substr(0, timing.find('\n')), "t_ns,ms,mode,frontend_ms,image_load_ms,estimator_ms,latency_ms,keyframe,solve_ms,covariance_ms,"
            "marginalization_ms");
  EXPECT_EQ(data_rows(timing), s["frames"].get<std::size_t>());
}

TEST_F(RunRealtimeCli, WithoutThePredictionTheFrontEndRunsAheadAndStillEqualsReplay) {
  const std::string no_prediction = " --no-plot --set frontend.imu_prediction=false";
  ASSERT_EQ(run(images(), path("replay-np"), no_prediction).status, 0);
  for (const std::string queue : {"1", "8"}) {
    const fs::path out = path("rt-np-" + queue);
    const auto rt = run(images(), out, no_prediction + " --realtime --realtime-queue " + queue);
    ASSERT_EQ(rt.status, 0) << rt.output;
    EXPECT_EQ(read_text(path("replay-np") / "trajectory.tum"), read_text(out / "trajectory.tum")) << "queue " << queue;
    EXPECT_EQ(summary(out)["realtime"]["frames_dropped"].get<std::size_t>(), 0u);
    EXPECT_LE(summary(out)["realtime"]["queue_max_depth"].get<std::size_t>(), std::stoul(queue));
  }
}

TEST_F(RunRealtimeCli, FeatureRecordingsRunInRealTimeToo) {
  const fs::path features = path("features");
  ASSERT_EQ(navaid_cli("simulate --scenario lab-walk-1 --mount hand --seed 3 --out '" + features.string() +
                       "' --set duration=5 --set simulation.mode=features")
                .status,
            0);
  ASSERT_EQ(run(features, path("f-replay"), " --no-plot").status, 0);
  const auto rt = run(features, path("f-rt"), " --no-plot --realtime --realtime-queue 2");
  ASSERT_EQ(rt.status, 0) << rt.output;
  EXPECT_EQ(read_text(path("f-replay") / "trajectory.tum"), read_text(path("f-rt") / "trajectory.tum"));
}

TEST_F(RunRealtimeCli, PacedRunsAccountForEveryFrame) {
  // Frames arrive at twice the recording's clock; whatever the machine's speed, every frame is
  // either estimated or counted as dropped, and the estimates stay in time order.
  const fs::path out = path("paced");
  const auto rt = run(images(), out, " --no-plot --realtime --realtime-speed 2 --realtime-queue 2");
  ASSERT_EQ(rt.status, 0) << rt.output;
  const auto s = summary(out);
  const auto& r = s["realtime"];
  EXPECT_EQ(r["speed"].get<double>(), 2.0);
  const std::size_t in = r["frontend_thread"]["frames_in"].get<std::size_t>();
  EXPECT_EQ(s["frames"].get<std::size_t>() + r["frames_dropped"].get<std::size_t>(), in);
  EXPECT_EQ(r["frontend_thread"]["frames_handed_over"].get<std::size_t>() + r["frontend_thread"]["skipped_stale"].get<std::size_t>(), in);
  // Paced, the wall time is at least the recording's duration over the speed.
  EXPECT_GE(s["pipeline"]["wall_s"].get<double>(), 0.9 * s["pipeline"]["recording_s"].get<double>() / 2.0);
  const auto trajectory = navaid::io::read_tum_trajectory(out / "trajectory.tum");
  ASSERT_GT(trajectory.size(), 10u);
  for (std::size_t i = 1; i < trajectory.size(); ++i) EXPECT_LT(trajectory[i - 1].t, trajectory[i].t);
}

TEST_F(RunRealtimeCli, DrawsTheTopViewAndSurvivesAPlotFailure) {
  const fs::path out = path("figure");
  const auto result = run(images(), out);
  ASSERT_EQ(result.status, 0) << result.output;
  const std::string png = read_text(out / "topview.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // The plotted track: every non-initializing estimate, in the ground truth's frame, with its mode.
  const std::string estimate = read_text(out / "topview.data" / "estimate.csv");
  EXPECT_EQ(estimate.substr(0, estimate.find('\n')), "t,x,y,z,mode");
  EXPECT_EQ(data_rows(estimate), navaid::io::read_tum_trajectory(out / "trajectory.tum").size());
  EXPECT_NE(estimate.find(",rgbd-vio\n"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "topview.data" / "groundtruth.csv"));

  // A figures folder without the script: a warning, the run itself succeeds.
  const fs::path empty = path("no-figures");
  fs::create_directories(empty);
  ASSERT_EQ(setenv("NAVAID_FIGURES_DIR", empty.c_str(), 1), 0);
  const auto unplotted = run(images(), path("figure-failed"));
  unsetenv("NAVAID_FIGURES_DIR");
  ASSERT_EQ(unplotted.status, 0) << unplotted.output;
  EXPECT_NE(unplotted.output.find("topview.png not drawn"), std::string::npos) << unplotted.output;
  EXPECT_FALSE(fs::exists(path("figure-failed") / "topview.png"));
  EXPECT_TRUE(fs::exists(path("figure-failed") / "summary.json"));

  // --no-plot: no figure at all.
  ASSERT_EQ(run(images(), path("unplotted"), " --no-plot").status, 0);
  EXPECT_FALSE(fs::exists(path("unplotted") / "topview.png"));
}

TEST_F(RunRealtimeCli, ClearErrors) {
  const auto negative = run(images(), path("bad"), " --realtime --realtime-speed -1");
  EXPECT_NE(negative.status, 0);
  EXPECT_NE(negative.output.find("--realtime-speed"), std::string::npos) << negative.output;
  const auto no_queue = run(images(), path("bad"), " --realtime --realtime-queue 0");
  EXPECT_NE(no_queue.status, 0);
  EXPECT_NE(no_queue.output.find("--realtime-queue"), std::string::npos) << no_queue.output;
  const auto without = run(images(), path("bad"), " --realtime-speed 2");
  EXPECT_NE(without.status, 0);
  EXPECT_NE(without.output.find("need --realtime"), std::string::npos) << without.output;
}

}  // namespace
