// The window's visual-inertial initialization (estimator.initialization.method hpnp / pnp): a walk
// joined while already moving, where the still start cannot find gravity.
#include <gtest/gtest.h>

#include <algorithm>

#include "navaid/core/errors.hpp"
#include "navaid/estimation/sliding_window_estimator.hpp"
#include "estimator_fixtures.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

// lab-walk-1 (hand) with its first 4 s cut: the recording starts mid-stride.
const io::Recording& moving_start() {
  static const io::Recording rec = [] {
    io::Recording r = testing::simulate_recording(
        "swi_walk", {"scenario=lab-walk-1", "mount=hand", "simulation.mode=features", "duration=16", "seed=2",
                     "sensor.camera.rate=15"});
    const Timestamp from = r.imu.front().t + seconds_to_ns(4.0);
    auto cut = [&](auto& v) {
      v.erase(std::remove_if(v.begin(), v.end(), [&](const auto& x) { return x.t < from; }), v.end());
    };
    cut(r.imu), cut(r.features), cut(r.gps), cut(r.mag);
    return r;
  }();
  return rec;
}

double speed_at_start(const io::Recording& rec) {
  for (const auto& g : rec.groundtruth)
    if (g.t >= rec.imu.front().t && g.v_W) return g.v_W->norm();
  return 0;
}

TEST(SlidingWindowInitialization, HpnpAndPnpStartAWalkJoinedWhileMoving) {
  const io::Recording& rec = moving_start();
  ASSERT_GT(speed_at_start(rec), 0.3) << "the cut recording should start in motion";
  for (const char* method : {"hpnp", "pnp"}) {
    SCOPED_TRACE(method);
    const auto run = testing::run_estimator(rec, {std::string("estimator.initialization.method=") + method});
    ASSERT_GT(run.stats.initialized_at_s, 0.0) << run.stats.last_initialization_failure;
    // Initialized within the first 3 s of the recording, after a full window of keyframes.
    EXPECT_LT(run.stats.initialized_at_s - ns_to_seconds(rec.imu.front().t), 3.0);
    const auto first = std::find_if(run.estimates.begin(), run.estimates.end(),
                                    [](const StateEstimate& e) { return e.mode != EstimatorMode::kInitializing; });
    ASSERT_NE(first, run.estimates.end());
    for (auto it = first; it != run.estimates.end(); ++it)
      ASSERT_NE(it->mode, EstimatorMode::kInitializing) << "initializing again";
    const double rmse = testing::position_rmse(run.estimates, rec.groundtruth);
    RecordProperty(std::string(method) + "_rmse_m", std::to_string(rmse));
    EXPECT_LT(rmse, 0.05);
  }
}

TEST(SlidingWindowInitialization, StillStartIsWrongWhenTheWalkStartsMoving) {
  // The still start takes the moving start's mean specific force for gravity: the visual
  // initialization is what makes such a recording usable.
  const io::Recording& rec = moving_start();
  const double still = testing::position_rmse(testing::run_estimator(rec, {}).estimates, rec.groundtruth);
  const double hpnp = testing::position_rmse(
      testing::run_estimator(rec, {"estimator.initialization.method=hpnp"}).estimates, rec.groundtruth);
  RecordProperty("still_rmse_m", std::to_string(still));
  EXPECT_LT(hpnp, still);
}

TEST(SlidingWindowInitialization, UnknownMethodNamesTheKey) {
  const std::string msg = navaid::testing::error_message<ConfigError>(
      [] { testing::run_estimator(moving_start(), {"estimator.initialization.method=sfm"}); });
  EXPECT_NE(msg.find("estimator.initialization.method"), std::string::npos) << msg;
}

}  // namespace
}  // namespace navaid::estimation
