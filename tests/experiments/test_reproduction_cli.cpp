// navaid reproduce end to end on a tiny matrix (the registered one takes minutes): the listing,
// a three-method table from real simulations and estimator runs, the figure, resuming, bad names.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

TEST(ReproduceCli, ListsTheReproductions) {
  const auto run = navaid_cli("reproduce --list");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("rgbd-vio-table1"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("produces:"), std::string::npos) << run.output;
}

TEST(ReproduceCli, UnknownNamesAndMissingOutAreUsageErrors) {
  const auto unknown = navaid_cli("reproduce no-such-table --out /tmp/never");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("known: rgbd-vio-table1"), std::string::npos) << unknown.output;
  const auto no_out = navaid_cli("reproduce rgbd-vio-table1");
  EXPECT_EQ(no_out.status, 2);
  EXPECT_NE(no_out.output.find("--out"), std::string::npos) << no_out.output;
}

TEST(ReproduceCli, RunsATinyTableWithTheFigureAndResumes) {
  ScratchDir dir("reproduce_cli");
  // 4 s of the corridor, the three methods of rgbd-vio-table1, two seeds.
  write_text(dir / "m.yaml", R"(
recordings:
  - name: corridor
    simulate: {scenario: corridor, set: [simulation.mode=features, duration=4]}
variants:
  - name: rgbd-vio
  - name: vins-fusion-rgbd
    set: [estimator.features.far_threshold=0.1, estimator.features.far_policy=free]
  - name: vins-rgbd
    set: [estimator.features.far_threshold=0.1, estimator.features.far_policy=fixed]
seeds: [1, 2]
metrics: [ate.rmse_m]
)");
  const fs::path out = dir / "out";
  const std::string cmd =
      "reproduce rgbd-vio-table1 --matrix '" + (dir / "m.yaml").string() + "' --jobs 2 --out '" + out.string() + "'";
  const auto run = navaid_cli(cmd);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("1 recordings x 3 variants x 2 seeds = 6 cells"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("# Verdict"), std::string::npos) << run.output;
  const std::string table = read_text(out / "table1.md");
  EXPECT_NE(table.find("| corridor |"), std::string::npos) << table;
  EXPECT_NE(table.find("| 0.269 |"), std::string::npos) << table;  // the paper's mean beside ours
  EXPECT_NE(table.find("6 cells (6 run, 0 resumed, 0 failed)"), std::string::npos) << table;
  EXPECT_NE(read_text(out / "table1.csv").find("change_of_means,,rgbd-vio,vins-rgbd,2,"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "verdict.md"));
  EXPECT_TRUE(fs::exists(out / "trajectories.png"));
  EXPECT_NE(read_text(out / "trajectories.csv").find("\nvins-fusion-rgbd,"), std::string::npos);

  const auto again = navaid_cli(cmd + " --no-plot");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("(6 finished before)"), std::string::npos) << again.output;
  EXPECT_NE(read_text(out / "table1.md").find("6 cells (0 run, 6 resumed, 0 failed)"), std::string::npos);
}
