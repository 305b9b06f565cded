// Cost of evaluating a trajectory, as `navaid eval` and the ablation runner do once per cell:
// time association (greedy closest-first over candidate pairs), Umeyama alignment per mode, and
// RPE over one sub-trajectory length. Inputs: the real EuRoC V1_02 estimate and ground truth
// (1355 poses at 20 Hz against 16702 at 200 Hz) when ../shared/data is present, else skipped.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "navaid/evaluation/absolute_trajectory_error.hpp"
#include "navaid/evaluation/chi_square.hpp"
#include "navaid/evaluation/relative_pose_error.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace {

namespace fs = std::filesystem;
namespace ev = navaid::evaluation;

struct Data {
  std::vector<navaid::io::StampedPose> est, gt;
  std::vector<ev::PosePair> pairs;
  bool ok = false;
};

const Data& data() {
  static const Data d = [] {
    Data x;
    const fs::path dir = fs::path(NAVAID_SHARED_DATA_DIR) / "rpg-euroc-V1_02" / "vislam_rp";
    if (!fs::exists(dir)) return x;
    x.est = navaid::io::read_tum_trajectory(dir / "stamped_traj_estimate0.txt");
    x.gt = navaid::io::read_tum_trajectory(dir / "stamped_groundtruth.txt");
    x.pairs = ev::associate_poses(x.est, x.gt);
    x.ok = true;
    return x;
  }();
  return d;
}

void BM_Associate(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  for (auto _ : state) benchmark::DoNotOptimize(ev::associate_poses(data().est, data().gt));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().est.size()));
}
BENCHMARK(BM_Associate)->Unit(benchmark::kMicrosecond);

void BM_Ate(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  const auto mode = static_cast<ev::AlignmentMode>(state.range(0));
  state.SetLabel(std::string(ev::to_string(mode)));
  for (auto _ : state) benchmark::DoNotOptimize(ev::compute_ate(data().pairs, {mode, 0}));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().pairs.size()));
}
BENCHMARK(BM_Ate)
    ->Arg(static_cast<int>(ev::AlignmentMode::kPosYaw))
    ->Arg(static_cast<int>(ev::AlignmentMode::kSe3))
    ->Arg(static_cast<int>(ev::AlignmentMode::kSim3))
    ->Unit(benchmark::kMicrosecond);

void BM_Rpe(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  const double length = static_cast<double>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(ev::compute_rpe(data().pairs, length));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().pairs.size()));
}
BENCHMARK(BM_Rpe)->Arg(5)->Arg(30)->Unit(benchmark::kMicrosecond);

// The ANEES bounds of a long Monte-Carlo study: chi-square quantiles at N * dof = 3e4.
void BM_ChiSquareQuantile(benchmark::State& state) {
  const double dof = static_cast<double>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(ev::chi_square_quantile(0.975, dof));
}
BENCHMARK(BM_ChiSquareQuantile)->Arg(3)->Arg(30000);

}  // namespace
