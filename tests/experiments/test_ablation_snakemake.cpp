// The jobs of a Snakemake study (ablation_snakemake.hpp): what `navaid ablate-job` does with one
// plan entry, and how the study folder reads back. The whole path, with Snakemake and a real
// Slurm cluster, is tests/cluster/slurm_study.sh.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/ablation.hpp"
#include "navaid/experiments/ablation_snakemake.hpp"
#include "test_support.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::write_text;

nlohmann::json cell_job(const fs::path& folder, const std::vector<std::string>& argv, const std::string& needs = "",
                        const fs::path& recording = {}) {
  return {{"id", "cell/r/v/1"},          {"kind", "cell"},    {"argv", argv},
          {"folder", folder.string()},    {"log", folder.string() + ".log"},
          {"recording", recording.string()}, {"needs", needs}, {"marker", (folder / "cell.done").string()}};
}

fs::path write_plan(const fs::path& dir, const nlohmann::json& jobs) {
  const fs::path plan = dir / "plan.json";
  write_text(plan, nlohmann::json{{"version", 1}, {"jobs", jobs}}.dump());
  return plan;
}

TEST(AblationJob, AFailingCellIsRecordedAndTheJobStillSucceeds) {
  ScratchDir dir("ablation-job-fail");
  const fs::path folder = dir / "cells" / "r" / "v" / "seed1";
  const fs::path plan = write_plan(dir.path(), nlohmann::json::array({cell_job(folder, {"/bin/false"})}));
  run_ablation_job(plan, "cell/r/v/1");
  EXPECT_TRUE(fs::exists(folder / "cell.done"));
  EXPECT_NE(testing::read_text(folder / "failure.txt").find("the run exited with status 1"), std::string::npos);
  EXPECT_TRUE(fs::exists(folder / kCellSecondsFile));
}

TEST(AblationJob, ACellWhoseRecordingFailedSaysSo) {
  ScratchDir dir("ablation-job-recording");
  const fs::path recording = dir / "recordings" / "r" / "seed1";
  write_text(recording.string() + ".failure", "navaid simulate failed (see x.log)\n");
  const fs::path folder = dir / "cells" / "r" / "v" / "seed1";
  const fs::path plan = write_plan(
      dir.path(), nlohmann::json::array({cell_job(folder, {"/bin/true"}, recording.string() + ".simulated", recording)}));
  run_ablation_job(plan, "cell/r/v/1");
  EXPECT_EQ(testing::read_text(folder / "failure.txt"), "recording not available: navaid simulate failed (see x.log)\n");
}

TEST(AblationJob, ACellThatWritesItsSummaryIsDoneWithItsTime) {
  ScratchDir dir("ablation-job-done");
  const fs::path folder = dir / "cells" / "r" / "v" / "seed1";
  // The "run" writes summary.json into the cell folder, as navaid run does.
  const fs::path plan = write_plan(
      dir.path(),
      nlohmann::json::array({cell_job(folder, {"/bin/sh", "-c", "echo '{\"ate\": {\"rmse_m\": 0.25}}' > \"$0\"",
                                               (folder / "summary.json").string()})}));
  run_ablation_job(plan, "cell/r/v/1");
  EXPECT_FALSE(fs::exists(folder / "failure.txt"));
  AblationMatrix m;
  m.recordings = {{"r", fs::path("/somewhere"), "", {}}};
  m.variants = {{"v", {}}};
  const CellOutcome o = read_ablation_cell(m, {0, 0, 1}, dir.path());
  EXPECT_EQ(o.status, CellStatus::kDone);
  EXPECT_EQ(o.metrics.at("ate.rmse_m"), 0.25);
  EXPECT_GT(o.seconds, 0.0);
  // Without the job's time it is a resumed cell; without anything it has not run.
  fs::remove(folder / kCellSecondsFile);
  EXPECT_EQ(read_ablation_cell(m, {0, 0, 1}, dir.path()).status, CellStatus::kResumed);
  fs::remove_all(folder);
  const CellOutcome none = read_ablation_cell(m, {0, 0, 1}, dir.path());
  EXPECT_EQ(none.status, CellStatus::kFailed);
  EXPECT_EQ(none.error, "the cell has not run");
}

TEST(AblationJob, UnknownJobsAndBadPlansAreErrors) {
  ScratchDir dir("ablation-job-bad");
  const fs::path plan = write_plan(dir.path(), nlohmann::json::array());
  EXPECT_THROW(run_ablation_job(plan, "cell/x/y/1"), Error);
  write_text(dir / "broken.json", "{not json");
  EXPECT_THROW(run_ablation_job(dir / "broken.json", "cell/x/y/1"), IoError);
  EXPECT_THROW(run_ablation_job(dir / "missing.json", "cell/x/y/1"), IoError);
}

}  // namespace
}  // namespace navaid::experiments
