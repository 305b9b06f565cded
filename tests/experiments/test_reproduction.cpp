// Reproductions: the registry, the comparison table and its verdict on constructed results, the
// adapted matrix (seeds, quick subset, stale results), the aligned trajectories of the figure, and
// a whole table reproduction with fake hooks (resuming included).
#include "navaid/experiments/reproduction.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <fstream>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction_comparison.hpp"
#include "navaid/experiments/reproduction_matrix.hpp"
#include "navaid/experiments/reproduction_table_runner.hpp"
#include "navaid/experiments/reproduction_trajectories.hpp"
#include "navaid/experiments/reproduction_verdict.hpp"
#include "navaid/io/tum_trajectory.hpp"
#include "test_support.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;
using testing::read_text;
using testing::ScratchDir;
using testing::write_text;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Two recordings x three methods x seeds {1, 2, 3}; value(r, v, seed) given by a function.
struct Study {
  AblationMatrix m;
  std::vector<CellOutcome> outcomes;

  template <class F>
  Study(F value, std::vector<AblationCell> failing = {}) {
    m.recordings = {{"walk-a", std::nullopt, "lab-walk-1", {}}, {"walk-b", std::nullopt, "lab-walk-2", {}}};
    m.variants = {{"proposed", {}}, {"base-1", {"x=1"}}, {"base-2", {"x=2"}}};
    m.seeds = {1, 2, 3};
    m.metrics = {"ate.rmse_m"};
    for (const auto& c : ablation_cells(m)) {
      CellOutcome o;
      o.cell = c;
      const bool fails = std::any_of(failing.begin(), failing.end(), [&](const AblationCell& f) {
        return f.recording == c.recording && f.variant == c.variant && f.seed == c.seed;
      });
      o.status = fails ? CellStatus::kFailed : CellStatus::kDone;
      if (!fails) o.metrics["ate.rmse_m"] = value(c.recording, c.variant, c.seed);
      outcomes.push_back(o);
    }
  }
};

PaperNumbers paper() {
  PaperNumbers p;
  p.source = "the paper";
  p.mean_by_method = {{"proposed", 0.269}, {"base-1", 0.359}};
  p.change_by_baseline = {{"base-1", -0.252}, {"base-2", -0.254}};
  p.rows_best = 4;
  p.rows_total = 5;
  p.missing_note = "Per-row numbers are not in our copy.";
  return p;
}

TEST(Reproduction, RegistryListsRgbdVioTable1) {
  ASSERT_FALSE(reproductions().empty());
  const Reproduction& r = find_reproduction("rgbd-vio-table1");
  EXPECT_EQ(r.matrix_file, "rgbd-vio-table1.yaml");
  EXPECT_TRUE(r.run);
  const std::string list = reproduction_listing();
  EXPECT_TRUE(contains(list, "rgbd-vio-table1")) << list;
  EXPECT_TRUE(contains(list, "Table I")) << list;
  const auto e = testing::expect_throw<UsageError>([] { find_reproduction("no-such-table"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "rgbd-vio-table1")) << e->what();  // the message lists the known names

  ReproductionRequest request;
  request.matrices_dir = "/m";
  EXPECT_EQ(reproduction_matrix_file(r, request), fs::path("/m/rgbd-vio-table1.yaml"));
  request.matrix = "/elsewhere/x.yaml";
  EXPECT_EQ(reproduction_matrix_file(r, request), fs::path("/elsewhere/x.yaml"));
}

TEST(Reproduction, TheRegisteredMatrixReadsAndDefinesTheThreeMethods) {
  const AblationMatrix m = read_ablation_matrix(fs::path(NAVAID_SOURCE_DIR) / "experiments/reproductions/rgbd-vio-table1.yaml");
  ASSERT_EQ(m.recordings.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(m.recordings[i].scenario, "lab-walk-" + std::to_string(i + 1));
    EXPECT_NE(std::find(m.recordings[i].simulate_overrides.begin(), m.recordings[i].simulate_overrides.end(),
                        "simulation.mode=features"),
              m.recordings[i].simulate_overrides.end());
  }
  ASSERT_EQ(m.variants.size(), 3u);
  EXPECT_EQ(m.variants[0].name, "rgbd-vio");
  // HPnP for the proposed method, 3D-2D PnP for both baselines; depth fixed only in VINS-RGBD.
  const auto has = [](const AblationVariant& v, const std::string& set) {
    return std::find(v.overrides.begin(), v.overrides.end(), set) != v.overrides.end();
  };
  EXPECT_TRUE(has(m.variants[0], "estimator.initialization.method=hpnp"));
  for (std::size_t v = 1; v < 3; ++v) EXPECT_TRUE(has(m.variants[v], "estimator.initialization.method=pnp"));
  EXPECT_EQ(m.variants[2].name, "vins-rgbd");
  EXPECT_TRUE(has(m.variants[2], "estimator.features.far_policy=fixed"));
  EXPECT_TRUE(has(m.variants[1], "estimator.features.far_policy=free"));
  // All three are VINS-Mono windows: exact anchor bearings, re-anchored tracks reused, robust
  // weights in the prior.
  for (const auto& v : m.variants) {
    EXPECT_TRUE(has(v, "estimator.features.anchor_bearing=fixed")) << v.name;
    EXPECT_TRUE(has(v, "estimator.features.leaving_anchor=reuse")) << v.name;
    EXPECT_TRUE(has(v, "estimator.prior_weights=robust")) << v.name;
  }
  EXPECT_TRUE(has(m.variants[0], "estimator.depth.point_covariance=paper"));
  EXPECT_GE(m.seeds.size(), 5u);
  EXPECT_EQ(m.metrics.front(), "ate.rmse_m");
}

TEST(Reproduction, ComparisonTableFromConstructedResults) {
  // proposed = 1 + seed/10 (walk-a) or 2 + seed/10 (walk-b); base-1 = twice proposed; base-2 =
  // proposed + 0.5 except a failing cell.
  const Study s(
      [](std::size_t r, std::size_t v, std::uint64_t seed) {
        const double p = 1.0 + static_cast<double>(r) + 0.1 * static_cast<double>(seed);
        return v == 0 ? p : v == 1 ? 2.0 * p : p + 0.5;
      },
      {{1, 2, 3}});
  ComparisonOptions options;
  options.bootstrap_resamples = 2000;
  const MethodComparison c = compare_methods(s.m, s.outcomes, "ate.rmse_m", options);
  ASSERT_EQ(c.cells.size(), 2u);
  ASSERT_TRUE(c.cells[0][0]);
  EXPECT_NEAR(c.cells[0][0]->mean, 1.2, 1e-12);  // mean of 1.1, 1.2, 1.3
  EXPECT_NEAR(c.cells[0][0]->std, 0.1, 1e-12);
  const double half = 4.302652729749464 * 0.1 / std::sqrt(3.0);
  EXPECT_NEAR(c.cells[0][0]->high, 1.2 + half, 1e-9);
  EXPECT_EQ(c.cells[1][2]->n, 2u);  // seed 3 failed
  EXPECT_EQ(c.expected[1][2], 3u);
  EXPECT_EQ(c.best[0], 0u);
  EXPECT_EQ(c.best[1], 0u);
  // Mean over recordings per seed: proposed (1.1 + 2.1) / 2 ... -> mean 1.7; base-2 only seeds
  // 1 and 2 are finished on both recordings.
  EXPECT_NEAR(c.overall[0]->mean, 1.7, 1e-12);
  EXPECT_EQ(c.overall[0]->n, 3u);
  EXPECT_EQ(c.overall[2]->n, 2u);
  EXPECT_NEAR(c.overall[2]->mean, (1.6 + 2.6 + 1.7 + 2.7) / 4.0, 1e-12);
  // base-1 is exactly twice: -50 % with a collapsed interval, 6 pairs; base-2 has 5 pairs.
  EXPECT_EQ(c.change_of_means[1]->pairs, 6u);
  EXPECT_NEAR(c.change_of_means[1]->estimate, -0.5, 1e-12);
  EXPECT_NEAR(c.change_of_means[1]->low, -0.5, 1e-12);
  EXPECT_NEAR(c.change_per_pair[1]->high, -0.5, 1e-12);
  EXPECT_EQ(c.change_of_means[2]->pairs, 5u);
  EXPECT_FALSE(c.change_of_means[0]);

  const std::string md = comparison_markdown(c, paper(), "Table");
  EXPECT_TRUE(contains(md, "### Table")) << md;
  EXPECT_TRUE(contains(md, "| walk-a | **1.2000 [")) << md;  // best per row in bold
  EXPECT_TRUE(contains(md, "(n=2/3)")) << md;
  EXPECT_TRUE(contains(md, "| 0.269 |")) << md;             // the paper's mean beside ours
  EXPECT_TRUE(contains(md, "| base-1 | 6 | -50.0 % [-50.0, -50.0] | -50.0 % [-50.0, -50.0] | -25.2 % |")) << md;
  EXPECT_TRUE(contains(md, "Per-row numbers are not in our copy.")) << md;

  const std::string csv = comparison_csv(c, paper());
  EXPECT_TRUE(contains(csv, "quantity,recording,method,baseline,n,value,std,ci_low,ci_high,paper\n")) << csv;
  EXPECT_TRUE(contains(csv, "mean,walk-a,proposed,,3,1.2,0.1,")) << csv;
  EXPECT_TRUE(contains(csv, "mean_over_recordings,,proposed,,3,1.7,")) << csv;
  EXPECT_TRUE(contains(csv, ",0.269\n")) << csv;
  EXPECT_TRUE(contains(csv, "change_of_means,,proposed,base-1,6,-0.5,,-0.5,-0.5,-0.252\n")) << csv;

  EXPECT_THROW(compare_methods(s.m, s.outcomes, "nees.position_mean"), Error);
  AblationMatrix one = s.m;
  one.variants.resize(1);
  EXPECT_THROW(compare_methods(one, s.outcomes, "ate.rmse_m"), Error);
}

TEST(Reproduction, ClassifiesAChangeAgainstThePaper) {
  auto change = [](double lo, double hi) { return std::optional<RelativeChange>(RelativeChange{25, 0.5 * (lo + hi), lo, hi}); };
  EXPECT_EQ(classify_change(std::nullopt, -0.25), ChangeFinding::kNoData);
  EXPECT_EQ(classify_change(change(0.05, 0.2), -0.25), ChangeFinding::kReversed);
  EXPECT_EQ(classify_change(change(-0.1, 0.02), -0.25), ChangeFinding::kNotSignificant);
  EXPECT_EQ(classify_change(change(-0.3, -0.2), -0.25), ChangeFinding::kLikePaper);
  EXPECT_EQ(classify_change(change(-0.15, -0.05), -0.25), ChangeFinding::kSmallerThanPaper);
  EXPECT_EQ(classify_change(change(-0.6, -0.4), -0.25), ChangeFinding::kLargerThanPaper);
  EXPECT_EQ(classify_change(change(-0.6, -0.4), std::nullopt), ChangeFinding::kBetterNoPaper);
  EXPECT_EQ(classify_change(RelativeChange{1, -0.3, NAN, NAN}, -0.25), ChangeFinding::kNoData);
}

TEST(Reproduction, VerdictFollowsTheNumbers) {
  // The proposed method 25 % below both baselines, its ratio jittered by seed (+-4 %, summing to
  // zero): ordering holds, and the interval around -25 % contains the paper's -25.2 % and -25.4 %.
  auto jitter = [](std::uint64_t seed) { return seed == 1 ? 0.04 : seed == 2 ? -0.04 : 0.0; };
  const Study like([&](std::size_t r, std::size_t v, std::uint64_t seed) {
    const double base = 1.0 + static_cast<double>(r);
    return v == 0 ? 0.75 * base * (1.0 + jitter(seed)) : base;
  });
  const Verdict v = judge_comparison(compare_methods(like.m, like.outcomes, "ate.rmse_m"), paper());
  EXPECT_TRUE(v.complete);
  EXPECT_TRUE(v.lowest_mean);
  EXPECT_TRUE(v.ordering_holds);
  EXPECT_TRUE(v.size_like_paper);
  EXPECT_EQ(v.rows_best, 2u);
  ASSERT_EQ(v.baselines.size(), 2u);
  EXPECT_EQ(v.baselines[0].finding, ChangeFinding::kLikePaper);

  // 60 % lower: the ordering holds, the size does not (larger than the paper's).
  const Study larger([&](std::size_t r, std::size_t v2, std::uint64_t seed) {
    const double base = 1.0 + static_cast<double>(r);
    return v2 == 0 ? 0.4 * base * (1.0 + jitter(seed)) : base;
  });
  const MethodComparison cl = compare_methods(larger.m, larger.outcomes, "ate.rmse_m");
  const Verdict vl = judge_comparison(cl, paper());
  EXPECT_TRUE(vl.ordering_holds);
  EXPECT_FALSE(vl.size_like_paper);
  EXPECT_EQ(vl.baselines[1].finding, ChangeFinding::kLargerThanPaper);
  const std::string text = verdict_markdown(vl, cl, paper());
  EXPECT_TRUE(contains(text, "**Ordering: holds.**")) << text;
  EXPECT_TRUE(contains(text, "by more than the paper")) << text;
  EXPECT_TRUE(contains(text, "(paper: 4 of 5)")) << text;
  EXPECT_TRUE(contains(text, "Paper: proposed 0.269 < base-1 0.359.")) << text;

  // The proposed method worse than base-2 on one recording and no better overall.
  const Study reversed([&](std::size_t r, std::size_t v2, std::uint64_t seed) {
    const double base = 1.0 + static_cast<double>(r) + jitter(seed);
    return v2 == 2 ? 0.8 * base : base * (v2 == 0 ? 1.0 : 1.5);
  });
  const MethodComparison cr = compare_methods(reversed.m, reversed.outcomes, "ate.rmse_m");
  const Verdict vr = judge_comparison(cr, paper());
  EXPECT_FALSE(vr.lowest_mean);
  EXPECT_FALSE(vr.ordering_holds);
  EXPECT_EQ(vr.rows_best, 0u);
  EXPECT_EQ(vr.baselines[1].finding, ChangeFinding::kReversed);
  EXPECT_TRUE(contains(verdict_markdown(vr, cr, paper()), "**Ordering: does not hold.**"));

  // A method without any finished cell: incomplete, no ordering.
  std::vector<AblationCell> all_base2;
  for (std::size_t r = 0; r < 2; ++r)
    for (std::uint64_t seed = 1; seed <= 3; ++seed) all_base2.push_back({r, 2, seed});
  const Study missing([](std::size_t, std::size_t v2, std::uint64_t) { return v2 == 0 ? 1.0 : 2.0; }, all_base2);
  const Verdict vm = judge_comparison(compare_methods(missing.m, missing.outcomes, "ate.rmse_m"), paper());
  EXPECT_FALSE(vm.complete);
  EXPECT_FALSE(vm.ordering_holds);
  EXPECT_EQ(vm.baselines[1].finding, ChangeFinding::kNoData);
}

TEST(Reproduction, SeedCountAndQuickSubset) {
  AblationMatrix m = Study([](std::size_t, std::size_t, std::uint64_t) { return 1.0; }).m;
  m.seeds = {3, 7};
  set_seed_count(m, 4);
  EXPECT_EQ(m.seeds, (std::vector<std::uint64_t>{3, 7, 8, 9}));
  set_seed_count(m, 1);
  EXPECT_EQ(m.seeds, (std::vector<std::uint64_t>{3}));
  set_seed_count(m, 0);
  EXPECT_EQ(m.seeds.size(), 1u);

  m.seeds = {1, 2, 3};
  m.recordings[1].simulate_overrides = {"mount=hand"};
  QuickSubset q;
  q.recordings = {"walk-b"};
  q.seeds = 2;
  q.simulate_overrides = {"duration=15"};
  q.suffix = "-15s";
  AblationMatrix quick = m;
  apply_quick_subset(quick, q, "m.yaml");
  ASSERT_EQ(quick.recordings.size(), 1u);
  EXPECT_EQ(quick.recordings[0].name, "walk-b-15s");
  EXPECT_EQ(quick.recordings[0].simulate_overrides, (std::vector<std::string>{"mount=hand", "duration=15"}));
  EXPECT_EQ(quick.seeds, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(quick.variants.size(), 3u);
  q.recordings = {"walk-z"};
  const auto e = testing::expect_throw<ConfigError>([&] { apply_quick_subset(m, q, "m.yaml"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "recordings");
  EXPECT_TRUE(contains(e->what(), "walk-z"));
}

TEST(Reproduction, StaleResultsAreRemovedWhenTheMatrixChanges) {
  ScratchDir dir("reproduction_stale");
  const fs::path out = dir / "out";
  AblationMatrix m = Study([](std::size_t, std::size_t, std::uint64_t) { return 1.0; }).m;
  auto make = [&](const fs::path& p) {
    fs::create_directories(p);
    write_text(p / "summary.json", "{}");
  };
  // Results from before any state was recorded are kept.
  make(out / "cells/walk-a/base-1/seed1");
  EXPECT_EQ(remove_stale_results(m, out), 0u);
  EXPECT_TRUE(fs::exists(out / "cells/walk-a/base-1/seed1"));
  make(out / "cells/walk-b/base-1/seed1");
  make(out / "cells/walk-a/base-2/seed1");
  make(out / "recordings/walk-a/seed1");
  make(out / "cells/walk-a/proposed/seed1");
  EXPECT_EQ(remove_stale_results(m, out), 0u);  // unchanged

  m.variants[1].overrides = {"x=10"};  // base-1 changed: its cells on both recordings go
  EXPECT_EQ(remove_stale_results(m, out), 2u);
  EXPECT_FALSE(fs::exists(out / "cells/walk-a/base-1"));
  EXPECT_FALSE(fs::exists(out / "cells/walk-b/base-1"));
  EXPECT_TRUE(fs::exists(out / "cells/walk-a/base-2/seed1"));

  m.recordings[0].simulate_overrides = {"duration=5"};  // walk-a re-simulated, all its cells go
  EXPECT_EQ(remove_stale_results(m, out), 2u);
  EXPECT_FALSE(fs::exists(out / "recordings/walk-a"));
  EXPECT_FALSE(fs::exists(out / "cells/walk-a"));

  m.run_overrides = {"estimator.window_size=8"};  // every variant's cells
  make(out / "cells/walk-b/proposed/seed2");
  EXPECT_EQ(remove_stale_results(m, out), 1u);
  EXPECT_FALSE(fs::exists(out / "cells/walk-b/proposed"));

  // A quick subset's renamed recordings leave the full study's state alone.
  AblationMatrix quick = m;
  quick.recordings.resize(1);
  quick.recordings[0].name = "walk-a-15s";
  make(out / "recordings/walk-b/seed1");
  EXPECT_EQ(remove_stale_results(quick, out), 0u);
  EXPECT_EQ(remove_stale_results(m, out), 0u);
  EXPECT_TRUE(fs::exists(out / "recordings/walk-b/seed1"));
}

// Ground truth: a walk along x with a turn; the estimate in a frame rotated by 30 degrees about z
// and shifted, with +-e in z alternating: after the 4-DOF alignment its ATE RMSE is e.
void write_walk(const fs::path& gt, const fs::path& est, double e, Timestamp t0 = 1'000'000'000) {
  std::vector<io::StampedPose> g, s;
  const SE3 T_est_gt(Quat(Eigen::AngleAxisd(0.5236, Vec3::UnitZ())), Vec3(4.0, -2.0, 0.3));
  for (int i = 0; i < 400; ++i) {
    const double x = 0.01 * i;
    const Vec3 p = i < 200 ? Vec3(x, 0.0, 1.2) : Vec3(2.0, x - 2.0, 1.2);
    const Timestamp t = t0 + static_cast<Timestamp>(i) * 5'000'000;  // 200 Hz
    g.push_back({t, SE3(Quat::Identity(), p)});
    if (i % 4 == 0) s.push_back({t, T_est_gt * SE3(Quat::Identity(), p + Vec3(0, 0, (i / 4) % 2 ? e : -e))});
  }
  io::write_tum_trajectory(gt, g);
  io::write_tum_trajectory(est, s);
}

TEST(Reproduction, AlignedTrajectoriesForTheFigure) {
  ScratchDir dir("reproduction_traj");
  write_walk(dir / "gt.tum", dir / "a.tum", 0.02);
  write_walk(dir / "gt.tum", dir / "b.tum", 0.05);
  const auto rmse = write_aligned_trajectories(dir / "gt.tum", {{"a", dir / "a.tum"}, {"b", dir / "b.tum"}}, dir / "t.csv");
  ASSERT_EQ(rmse.size(), 2u);
  EXPECT_NEAR(rmse[0], 0.02, 1e-6);
  EXPECT_NEAR(rmse[1], 0.05, 1e-6);
  const std::string csv = read_text(dir / "t.csv");
  EXPECT_EQ(csv.rfind("method,t,x,y,z\nground truth,0.0000,0.00000,0.00000,1.20000\n", 0), 0u) << csv.substr(0, 200);
  std::size_t gt_rows = 0, a_rows = 0;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    gt_rows += line.rfind("ground truth,", 0) == 0;
    a_rows += line.rfind("a,", 0) == 0;
  }
  EXPECT_EQ(gt_rows, 200u);  // thinned to 10 ms
  EXPECT_EQ(a_rows, 100u);
  // An aligned estimate lies on the ground truth horizontally (here at x = 0.04, y = 0, t = 0.02 s).
  const std::size_t at = csv.find("\na,0.0200,");
  ASSERT_NE(at, std::string::npos) << csv.substr(0, 400);
  double x = 0, y = 0;
  ASSERT_EQ(std::sscanf(csv.c_str() + at + 9, ",%lf,%lf", &x, &y), 2);
  EXPECT_NEAR(x, 0.04, 1e-5);
  EXPECT_NEAR(y, 0.0, 1e-5);

  write_walk(dir / "gt2.tum", dir / "late.tum", 0.01, 9'000'000'000);  // no time overlap
  EXPECT_THROW(write_aligned_trajectories(dir / "gt.tum", {{"late", dir / "late.tum"}}, dir / "t2.csv"), Error);
  EXPECT_THROW(write_aligned_trajectories(dir / "missing.tum", {}, dir / "t3.csv"), IoError);
}

TEST(Reproduction, TableReproductionWithFakeHooksWritesEverythingAndResumes) {
  ScratchDir dir("reproduction_run");
  write_text(dir / "m.yaml", R"(
recordings:
  - name: walk-a
    simulate: {scenario: lab-walk-1, set: [simulation.mode=features]}
  - name: walk-b
    simulate: {scenario: lab-walk-3, set: [simulation.mode=features]}
variants:
  - name: proposed
  - name: base-1
    set: [x=1]
  - name: base-2
    set: [x=2]
seeds: [1, 2, 3]
metrics: [ate.rmse_m]
)");
  std::atomic<int> simulations{0}, runs{0};
  std::vector<std::vector<std::string>> plots;
  std::string said;
  ReproductionEnvironment env;
  env.hooks = [&](const AblationMatrix& m, const fs::path&) {
    AblationHooks h;
    h.simulate = [&](const AblationRecording&, std::uint64_t, const fs::path& folder) {
      fs::create_directories(folder);
      write_walk(folder / "groundtruth.tum", folder / "unused.tum", 0.0);
      write_text(folder / "recording.yaml", "x");
      ++simulations;
    };
    h.run_cell = [&, m](const AblationCell& c, const fs::path& recording, const fs::path& folder) {
      const double e = 0.01 * (1.0 + static_cast<double>(c.variant)) * (1.0 + 0.1 * static_cast<double>(c.seed));
      write_walk(folder / "gt.tum", folder / "trajectory.tum", e);
      EXPECT_TRUE(fs::exists(recording / "recording.yaml"));
      write_text(folder / "summary.json", "{\"ate\": {\"rmse_m\": " + std::to_string(e) + "}}");
      ++runs;
      return 0;
    };
    return h;
  };
  env.plot = [&](const std::string& script, const std::vector<std::string>& args) {
    plots.push_back(args);
    EXPECT_EQ(script, "plot_reproduction_trajectories.py");
  };
  env.say = [&](const std::string& line) { said += line + "\n"; };

  TableReproductionSpec spec;
  spec.name = "test-table";
  spec.title = "Test table";
  spec.stem = "table1";
  spec.paper = paper();
  spec.figure_recording = "walk-b";
  spec.figure_title = "three methods";
  ReproductionRequest request;
  request.out = dir / "out";
  request.jobs = 2;
  run_table_reproduction(spec, dir / "m.yaml", request, env);
  EXPECT_EQ(simulations, 6);
  EXPECT_EQ(runs, 18);
  for (const char* f : {"table1.md", "table1.csv", "verdict.md", "results.csv", "trajectories.csv", "matrix-state.json"})
    EXPECT_TRUE(fs::exists(request.out / f)) << f;
  const std::string table = read_text(request.out / "table1.md");
  EXPECT_TRUE(contains(table, "| walk-a | **")) << table;
  EXPECT_TRUE(contains(table, "18 cells (18 run, 0 resumed, 0 failed)")) << table;
  EXPECT_TRUE(contains(read_text(request.out / "verdict.md"), "**Ordering: holds.**"));
  // The figure is of walk-b, seed 1, with the three methods.
  ASSERT_EQ(plots.size(), 1u);
  EXPECT_EQ(plots[0].front(), (request.out / "trajectories.csv").string());
  EXPECT_TRUE(contains(plots[0].back(), "walk-b seed 1")) << plots[0].back();
  EXPECT_TRUE(contains(read_text(request.out / "trajectories.csv"), "\nbase-2,")) << said;

  // Again with two seeds and base-2 changed: nothing simulated, only base-2's cells re-run.
  write_text(dir / "m.yaml", read_text(dir / "m.yaml").replace(read_text(dir / "m.yaml").find("x=2"), 3, "x=3"));
  request.seeds = 2;
  request.plot = false;
  run_table_reproduction(spec, dir / "m.yaml", request, env);
  EXPECT_EQ(simulations, 6);
  EXPECT_EQ(runs, 18 + 4);
  EXPECT_EQ(plots.size(), 1u);
  EXPECT_TRUE(contains(said, "stale")) << said;
  EXPECT_TRUE(contains(read_text(request.out / "table1.md"), "12 cells (4 run, 8 resumed, 0 failed)"));

  // The quick subset must name recordings of the matrix; the table's metric must be measured.
  request.quick = true;
  spec.quick.recordings = {"walk-c"};
  EXPECT_THROW(run_table_reproduction(spec, dir / "m.yaml", request, env), ConfigError);
  request.quick = false;
  spec.metric = "nees.position_mean";
  const auto e = testing::expect_throw<ConfigError>([&] { run_table_reproduction(spec, dir / "m.yaml", request, env); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key(), "metrics");
}

}  // namespace
}  // namespace navaid::experiments
