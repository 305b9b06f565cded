// Cost of evaluating a trajectory, as `navaid eval` and the ablation runner do once per cell:
// time association (greedy closest-first over candidate pairs), Umeyama alignment per mode, and
// RPE over one sub-trajectory length. Inputs: the real EuRoC V1_02 estimate and ground truth
// (1355 poses at 20 Hz against 16702 at 200 Hz) when ../shared/data is present, else skipped.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "navaid/experiments/absolute_trajectory_error.hpp"
#include "navaid/experiments/chi_square.hpp"
#include "navaid/experiments/relative_pose_error.hpp"
#include "navaid/experiments/time_association.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace {

namespace fs = std::filesystem;
namespace ex = navaid::experiments;

struct Data {
  std::vector<navaid::io::StampedPose> est, gt;
  std::vector<ex::PosePair> pairs;
  bool ok = false;
};

const Data& data() {
  static const Data d = [] {
    Data x;
    const fs::path dir = fs::path(NAVAID_SHARED_DATA_DIR) / "rpg-euroc-V1_02" / "vislam_rp";
    if (!fs::exists(dir)) return x;
    x.est = navaid::io::read_tum_trajectory(dir / "stamped_traj_estimate0.txt");
    x.gt = navaid::io::read_tum_trajectory(dir / "stamped_groundtruth.txt");
    x.pairs = ex::associate_poses(x.est, x.gt);
    x.ok = true;
    return x;
  }();
  return d;
}

void BM_Associate(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  for (auto _ : state) benchmark::DoNotOptimize(ex::associate_poses(data().est, data().gt));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().est.size()));
}
BENCHMARK(BM_Associate)->Unit(benchmark::kMicrosecond);

void BM_Ate(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  const auto mode = static_cast<ex::AlignmentMode>(state.range(0));
  state.SetLabel(std::string(ex::to_string(mode)));
  for (auto _ : state) benchmark::DoNotOptimize(ex::compute_ate(data().pairs, {mode, 0}));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().pairs.size()));
}
BENCHMARK(BM_Ate)
    ->Arg(static_cast<int>(ex::AlignmentMode::kPosYaw))
    ->Arg(static_cast<int>(ex::AlignmentMode::kSe3))
    ->Arg(static_cast<int>(ex::AlignmentMode::kSim3))
    ->Unit(benchmark::kMicrosecond);

void BM_Rpe(benchmark::State& state) {
  if (!data().ok) return state.SkipWithError("../shared/data not present");
  const double length = static_cast<double>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(ex::compute_rpe(data().pairs, length));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data().pairs.size()));
}
BENCHMARK(BM_Rpe)->Arg(5)->Arg(30)->Unit(benchmark::kMicrosecond);

// The ANEES bounds of a long Monte-Carlo study: chi-square quantiles at N * dof = 3e4.
void BM_ChiSquareQuantile(benchmark::State& state) {
  const double dof = static_cast<double>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(ex::chi_square_quantile(0.975, dof));
}
BENCHMARK(BM_ChiSquareQuantile)->Arg(3)->Arg(30000);

}  // namespace
