// Cost of one pose-change estimate (estimation/initialization/pose_change.hpp) on a synthetic
// two-view scene of 150 correspondences (a 0.3 m walking step, 0.3 px noise, depths 1-8 m), for
// HPnP and 3D-2D PnP with all or 3 depth features, and with 20 % outliers. Single thread.
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>

#include "navaid/estimation/initialization/pose_change.hpp"
#include "navaid/estimation/initialization/pose_change_scene.hpp"

namespace {

using namespace navaid;
using namespace navaid::estimation;

TwoViewScene scene(int depth_features, double outliers) {
  TwoViewSceneOptions o;
  o.points = 150;
  o.depth_features = depth_features;
  o.depth_noise_rel = 0.005;
  o.outlier_fraction = outliers;
  const double deg = 3.14159265358979323846 / 180.0;
  return make_two_view_scene(SE3(quat_from_rpy(2.0 * deg, -3.0 * deg, 6.0 * deg), Vec3(0.08, -0.03, -0.29)), o);
}

void run(benchmark::State& state, PoseChangeMethod method, int depth_features, double outliers) {
  cv::setNumThreads(1);
  const TwoViewScene s = scene(depth_features, outliers);
  const PoseChangeOptions options;
  int inliers = 0;
  for (auto _ : state) {
    const auto p = estimate_pose_change(s.correspondences, method, options);
    if (!p) state.SkipWithError("no pose");
    inliers = p ? p->inliers : 0;
    benchmark::DoNotOptimize(inliers);
  }
  state.counters["inliers"] = inliers;
}

void BM_Hpnp_AllDepth(benchmark::State& s) { run(s, PoseChangeMethod::kHybrid, -1, 0.0); }
void BM_Pnp_AllDepth(benchmark::State& s) { run(s, PoseChangeMethod::kPnp, -1, 0.0); }
void BM_Hpnp_3Depth(benchmark::State& s) { run(s, PoseChangeMethod::kHybrid, 3, 0.0); }
void BM_Hpnp_AllDepth_20pctOutliers(benchmark::State& s) { run(s, PoseChangeMethod::kHybrid, -1, 0.2); }
void BM_Pnp_AllDepth_20pctOutliers(benchmark::State& s) { run(s, PoseChangeMethod::kPnp, -1, 0.2); }

BENCHMARK(BM_Hpnp_AllDepth)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Pnp_AllDepth)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Hpnp_3Depth)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Hpnp_AllDepth_20pctOutliers)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Pnp_AllDepth_20pctOutliers)->Unit(benchmark::kMicrosecond);

}  // namespace
