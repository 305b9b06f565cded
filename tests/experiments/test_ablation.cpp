#include "navaid/experiments/ablation.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <mutex>
#include <set>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;
using testing::write_text;

const char* kMatrix = R"(
recordings:
  - name: lab1
    simulate: {scenario: lab-walk-1, set: [simulation.mode=features, duration=20]}
  - name: real
    path: data/real
variants:
  - name: base
  - name: vio
    set: [estimator.depth_factors=false]
seeds: [1, 2, 3]
metrics: [ate.rmse_m, frames]
run: [estimator.window=8]
)";

// A fake study: simulate writes recording.yaml; a cell's ATE is 1 + variant + seed/10 (real
// recordings: 5 + variant); `crash` names cells that fail.
struct FakeStudy {
  AblationMatrix m;
  std::set<std::string> crash;
  std::atomic<int> simulated{0}, runs{0};
  std::mutex mutex;
  std::vector<std::string> seen_recordings;

  AblationHooks hooks() {
    AblationHooks h;
    h.simulate = [this](const AblationRecording& rec, std::uint64_t seed, const fs::path& folder) {
      EXPECT_EQ(rec.scenario, "lab-walk-1");
      fs::create_directories(folder);
      write_text(folder / "recording.yaml", "seed " + std::to_string(seed));
      ++simulated;
    };
    h.run_cell = [this](const AblationCell& c, const fs::path& recording, const fs::path& folder) {
      ++runs;
      {
        std::lock_guard<std::mutex> lock(mutex);
        seen_recordings.push_back(recording.string());
      }
      const std::string id = m.variants[c.variant].name + "/" + std::to_string(c.seed);
      if (crash.count(id)) return 139;  // a segfaulting cell
      const double ate = m.recordings[c.recording].simulated() ? 1.0 + c.variant + 0.1 * c.seed : 5.0 + c.variant;
      write_text(folder / "summary.json", "{\"ate\": {\"rmse_m\": " + std::to_string(ate) + "}, \"frames\": 100}");
      return 0;
    };
    return h;
  }
};

TEST(Ablation, ReadsTheMatrixFile) {
  ScratchDir dir("ablation_read");
  write_text(dir / "m.yaml", kMatrix);
  const AblationMatrix m = read_ablation_matrix(dir / "m.yaml");
  ASSERT_EQ(m.recordings.size(), 2u);
  EXPECT_TRUE(m.recordings[0].simulated());
  EXPECT_EQ(m.recordings[0].simulate_overrides.size(), 2u);
  EXPECT_EQ(*m.recordings[1].path, dir / "data/real");  // relative to the file
  ASSERT_EQ(m.variants.size(), 2u);
  EXPECT_TRUE(m.variants[0].overrides.empty());
  EXPECT_EQ(m.variants[1].overrides.front(), "estimator.depth_factors=false");
  EXPECT_EQ(m.seeds, (std::vector<std::uint64_t>{1, 2, 3}));
  EXPECT_EQ(m.metrics.front(), "ate.rmse_m");
  EXPECT_EQ(m.run_overrides.front(), "estimator.window=8");
  // Simulated: 2 variants x 3 seeds; real: 2 variants x 1.
  EXPECT_EQ(ablation_cells(m).size(), 8u);
}

TEST(Ablation, BadMatrixFilesNameTheKey) {
  ScratchDir dir("ablation_bad");
  const std::pair<const char*, const char*> cases[] = {
      {"variants: [{name: a}]\nseeds: [1]\n", "recordings"},
      {"recordings: [{name: r, path: x, simulate: {scenario: s}}]\nvariants: [{name: a}]\n", "recordings[0]"},
      {"recordings: [{name: r, path: x}]\nvariants: [{name: a}, {name: a}]\n", "variants[1].name"},
      {"recordings: [{name: ../r, path: x}]\nvariants: [{name: a}]\n", "recordings[0].name"},
      {"recordings: [{name: r, path: x}]\nvariants: [{name: a, set: [nokey]}]\n", "variants[0].set[0]"},
      {"recordings: [{name: r, path: x}]\nvariants: [{name: a}]\nseeds: [1, -2]\n", "seeds[1]"},
      {"recordings: [{name: r, path: x}]\nvariants: [{name: a}]\nseed: [1]\n", "seed"},
      // Found by fuzz_tables: keys and paths that are not plain scalars escaped as yaml-cpp errors.
      {"recordings: [{name: r, simulate: {scenario: s,!set: [a=b]}}]\nvariants: [{name: a}]\n", "recordings[0].simulate"},
      {"recordings: [{name: r, path: x, [a]: 1}]\nvariants: [{name: a}]\n", "recordings[0]"},
      {"recordings: [{name: r, path: {a: 1}}]\nvariants: [{name: a}]\n", "recordings[0].path"},
  };
  for (const auto& [text, key] : cases) {
    write_text(dir / "m.yaml", text);
    const auto e = testing::expect_throw<ConfigError>([&] { read_ablation_matrix(dir / "m.yaml"); }, text);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key(), key) << text << " -> " << e->what();
  }
}

TEST(Ablation, RunsEveryCellInParallelSurvivesCrashesAndResumes) {
  ScratchDir dir("ablation_run");
  write_text(dir / "m.yaml", kMatrix);
  FakeStudy study;
  study.m = read_ablation_matrix(dir / "m.yaml");
  study.crash = {"vio/2"};
  const fs::path out = dir / "study";
  auto outcomes = run_ablation(study.m, out, 2, study.hooks());
  ASSERT_EQ(outcomes.size(), 8u);
  EXPECT_EQ(study.simulated, 3);  // once per seed, shared by both variants
  EXPECT_EQ(study.runs, 8);
  std::size_t failed = 0;
  for (const auto& o : outcomes) {
    if (o.status == CellStatus::kFailed) {
      ++failed;
      EXPECT_EQ(o.cell.seed, 2u);
      EXPECT_NE(o.error.find("status 139"), std::string::npos) << o.error;
      EXPECT_TRUE(fs::exists(cell_folder(study.m, o.cell, out) / "failure.txt"));
    } else {
      EXPECT_EQ(o.status, CellStatus::kDone);
      EXPECT_DOUBLE_EQ(o.metrics.at("frames"), 100.0);
    }
  }
  EXPECT_EQ(failed, 1u);

  // Second run: finished cells are kept, the failed one is retried (and now succeeds).
  study.crash.clear();
  study.runs = 0;
  outcomes = run_ablation(study.m, out, 2, study.hooks());
  EXPECT_EQ(study.simulated, 3);  // recordings are complete: not simulated again
  EXPECT_EQ(study.runs, 1);
  for (const auto& o : outcomes) EXPECT_NE(o.status, CellStatus::kFailed);

  write_ablation_csv(study.m, outcomes, out / "results.csv");
  const std::string csv = testing::read_text(out / "results.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "recording,variant,seed,status,seconds,ate.rmse_m,frames");
  EXPECT_NE(csv.find("lab1,vio,2,done,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("real,base,1,resumed,0.000,5,100"), std::string::npos) << csv;
}

TEST(Ablation, MarkdownTableHasMeansBestInBoldAndRelativeChange) {
  ScratchDir dir("ablation_md");
  write_text(dir / "m.yaml", kMatrix);
  FakeStudy study;
  study.m = read_ablation_matrix(dir / "m.yaml");
  const auto outcomes = run_ablation(study.m, dir / "study", 1, study.hooks());
  const std::string md = ablation_markdown(study.m, outcomes, "ate.rmse_m");
  // lab1: base 1.1, 1.2, 1.3 -> 1.2 ± 0.1 (bold: best); vio 2.2 ± 0.1. real: 5 vs 6.
  EXPECT_NE(md.find("| lab1 | **1.2 ± 0.1** | 2.2 ± 0.1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| real | **5** | 6 |"), std::string::npos) << md;
  // Means over recordings: base 3.1, vio 4.1 -> +32.3 %.
  EXPECT_NE(md.find("| mean | 3.1 | 4.1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| vs base | +0.0 % | +32.3 % |"), std::string::npos) << md;
}

TEST(Ablation, AFailedRecordingFailsItsCellsOnly) {
  ScratchDir dir("ablation_recfail");
  write_text(dir / "m.yaml", kMatrix);
  FakeStudy study;
  study.m = read_ablation_matrix(dir / "m.yaml");
  AblationHooks hooks = study.hooks();
  hooks.simulate = [](const AblationRecording&, std::uint64_t seed, const fs::path& folder) {
    if (seed == 3) throw Error("scenario exploded");
    fs::create_directories(folder);
    write_text(folder / "recording.yaml", "ok");
  };
  const auto outcomes = run_ablation(study.m, dir / "study", 2, hooks);
  for (const auto& o : outcomes) {
    const bool should_fail = study.m.recordings[o.cell.recording].simulated() && o.cell.seed == 3;
    EXPECT_EQ(o.status == CellStatus::kFailed, should_fail);
    if (should_fail) {
      EXPECT_NE(o.error.find("scenario exploded"), std::string::npos);
    }
  }
  const std::string md = ablation_markdown(study.m, outcomes, "ate.rmse_m");
  EXPECT_NE(md.find("(n=2/3)"), std::string::npos) << md;
}

}  // namespace
}  // namespace navaid::experiments
