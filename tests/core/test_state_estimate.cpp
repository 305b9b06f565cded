// StateEstimate's mode names: to_string and estimator_mode_from_string from one table.
#include <gtest/gtest.h>

#include <string_view>
#include <utility>
#include <vector>

#include "navaid/core/state_estimate.hpp"

namespace navaid {
namespace {

TEST(EstimatorModeNames, EveryModeRoundTripsThroughItsName) {
  // Every enumerator with the name written in runs and logs; a dropped or misspelt table entry fails.
  const std::vector<std::pair<EstimatorMode, std::string_view>> modes{
      {EstimatorMode::kInitializing, "initializing"},
      {EstimatorMode::kRgbdVio, "rgbd-vio"},
      {EstimatorMode::kVio, "vio"},
      {EstimatorMode::kImuOnly, "imu-only"},
      {EstimatorMode::kLost, "lost"},
  };
  for (const auto& [mode, name] : modes) {
    EXPECT_EQ(to_string(mode), name);
    EXPECT_EQ(estimator_mode_from_string(name), mode) << name;
    EXPECT_EQ(estimator_mode_from_string(to_string(mode)), mode) << name;
  }
}

TEST(EstimatorModeNames, UnknownNameAndValue) {
  EXPECT_EQ(estimator_mode_from_string("RGBD-VIO"), std::nullopt);
  EXPECT_EQ(estimator_mode_from_string("unknown"), std::nullopt);
  EXPECT_EQ(to_string(static_cast<EstimatorMode>(42)), "unknown");
}

}  // namespace
}  // namespace navaid
