// navaid ablate end to end: simulated recordings, two variants, two seeds, a failing variant,
// resuming, the results table and figure.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "test_support.hpp"

namespace fs = std::filesystem;
using navaid::testing::navaid_cli;
using navaid::testing::read_text;
using navaid::testing::ScratchDir;
using navaid::testing::write_text;

TEST(AblateCli, RunsAStudyRecordsAFailingVariantAndResumes) {
  ScratchDir dir("ablate_cli");
  write_text(dir / "m.yaml", R"(
recordings:
  - name: corridor
    simulate: {scenario: corridor, set: [simulation.mode=features, duration=4]}
variants:
  - name: rgbd-vio
  - name: vio
    set: [estimator.depth.enabled=false]
  - name: broken
    set: [estimator.no_such_key=1]
seeds: [1, 2]
metrics: [ate.rmse_m, frames]
)");
  const std::string cmd = "ablate '" + (dir / "m.yaml").string() + "' --jobs 2 --out '" + (dir / "study").string() + "'";
  const auto run = navaid_cli(cmd);
  ASSERT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find("6 cells: 4 run, 0 resumed, 2 failed"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("failed: corridor/broken/seed1"), std::string::npos) << run.output;
  const std::string csv = read_text(dir / "study" / "results.csv");
  EXPECT_NE(csv.find("corridor,rgbd-vio,2,done,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("corridor,broken,1,failed,"), std::string::npos) << csv;
  const std::string md = read_text(dir / "study" / "results.md");
  EXPECT_NE(md.find("| corridor |"), std::string::npos) << md;
  EXPECT_NE(md.find("failed |"), std::string::npos) << md;
  EXPECT_TRUE(fs::exists(dir / "study" / "ablation.png"));
  // The failing cell's log names the bad key.
  EXPECT_NE(read_text(dir / "study" / "cells" / "corridor" / "broken" / "seed1.log").find("estimator.no_such_key"),
            std::string::npos);

  // Again: the four finished cells are kept, the two failing ones are retried (and fail again).
  const auto again = navaid_cli(cmd + " --no-plot");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("6 cells: 0 run, 4 resumed, 2 failed"), std::string::npos) << again.output;
}
