// navaid reproduce end to end on a tiny matrix (the registered one takes minutes): the listing,
// a three-method table from real simulations and estimator runs, the figure, resuming, bad names.
#include <gtest/gtest.h>

#include <algorithm>
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

TEST(ReproduceCli, SmartCaneTable1QuickHasBothPlannersThePaperAndAVerdict) {
  ScratchDir dir("reproduce_smart_cane");
  const fs::path out = dir / "out";
  const auto run = navaid_cli("reproduce smart-cane-table1 --quick --out '" + out.string() + "'");
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("2 maps x 2 planners x 5 pairs"), std::string::npos) << run.output;
  const std::string table = read_text(out / "table1.md");
  EXPECT_NE(table.find("## office1"), std::string::npos) << table;
  EXPECT_NE(table.find("## pillar"), std::string::npos) << table;
  EXPECT_NE(table.find("13290.9"), std::string::npos) << table;  // the paper's A* nodes on office1
  EXPECT_NE(read_text(out / "verdict.md").find("nodes expanded** of wpg vs astar"), std::string::npos);
  // Nodes are deterministic: the footstep search expands far fewer than A* on both maps.
  const std::string csv = read_text(out / "table1.csv");
  for (const std::string map : {"office1", "pillar"}) {
    const auto value = [&](const std::string& planner) {
      const std::string key = map + "," + planner + ",nodes,avg,";
      const auto at = csv.find(key);
      EXPECT_NE(at, std::string::npos) << key << "\n" << csv;
      return std::stod(csv.substr(at + key.size()));
    };
    EXPECT_LT(value("wpg"), 0.2 * value("astar")) << map;
  }
  // Every planner on every pair, one line each.
  const std::string runs = read_text(out / "runs.csv");
  EXPECT_EQ(std::count(runs.begin(), runs.end(), '\n'), 1 + 2 * 2 * 5) << runs;
  EXPECT_TRUE(fs::exists(out / "paths-office1.png"));
  EXPECT_TRUE(fs::exists(out / "paths-pillar.png"));
}

TEST(ReproduceCli, SmartCaneTable1BadSpecsAreClearErrors) {
  ScratchDir dir("reproduce_smart_cane_bad");
  write_text(dir / "one.yaml", "maps: [{name: pillar}]\nplanners: [{name: wpg}]\n");
  const auto one = navaid_cli("reproduce smart-cane-table1 --matrix '" + (dir / "one.yaml").string() + "' --out '" +
                              (dir / "o1").string() + "'");
  EXPECT_EQ(one.status, 2);
  EXPECT_NE(one.output.find("planners"), std::string::npos) << one.output;
  write_text(dir / "unknown.yaml", "maps: [{name: pillar}]\nplanners: [{name: wpg}, {name: dijkstra}]\n");
  const auto unknown = navaid_cli("reproduce smart-cane-table1 --matrix '" + (dir / "unknown.yaml").string() +
                                  "' --out '" + (dir / "o2").string() + "'");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("unknown planner 'dijkstra'"), std::string::npos) << unknown.output;
  write_text(dir / "nomap.yaml", "maps: [{name: atlantis}]\nplanners: [{name: wpg}, {name: astar}]\n");
  const auto nomap = navaid_cli("reproduce smart-cane-table1 --matrix '" + (dir / "nomap.yaml").string() +
                                "' --out '" + (dir / "o3").string() + "'");
  EXPECT_EQ(nomap.status, 2);
  EXPECT_NE(nomap.output.find("atlantis"), std::string::npos) << nomap.output;
  write_text(dir / "badset.yaml",
             "maps: [{name: pillar, set: {rrt: [a=1]}}]\nplanners: [{name: wpg}, {name: astar}]\n");
  const auto badset = navaid_cli("reproduce smart-cane-table1 --matrix '" + (dir / "badset.yaml").string() +
                                 "' --out '" + (dir / "o4").string() + "'");
  EXPECT_EQ(badset.status, 2);
  EXPECT_NE(badset.output.find("names no planner 'rrt'"), std::string::npos) << badset.output;
  write_text(dir / "typo.yaml", "maps: [{name: pillar, min_distance: 20}]\nplanners: [{name: wpg}, {name: astar}]\n");
  const auto typo = navaid_cli("reproduce smart-cane-table1 --matrix '" + (dir / "typo.yaml").string() + "' --out '" +
                               (dir / "o5").string() + "'");
  EXPECT_EQ(typo.status, 2);
  EXPECT_NE(typo.output.find("key 'maps[0].min_distance': unknown key"), std::string::npos) << typo.output;
}
