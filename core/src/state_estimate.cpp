#include "navaid/core/state_estimate.hpp"

#include <array>
#include <utility>

namespace navaid {
namespace {
constexpr std::array<std::pair<EstimatorMode, std::string_view>, 5> kModeNames{{
    {EstimatorMode::kInitializing, "initializing"},
    {EstimatorMode::kRgbdVio, "rgbd-vio"},
    {EstimatorMode::kVio, "vio"},
    {EstimatorMode::kImuOnly, "imu-only"},
    {EstimatorMode::kLost, "lost"},
}};
}  // namespace

std::string_view to_string(EstimatorMode mode) {
  for (const auto& [m, name] : kModeNames)
    if (m == mode) return name;
  return "unknown";
}

std::optional<EstimatorMode> estimator_mode_from_string(std::string_view name) {
  for (const auto& [m, n] : kModeNames)
    if (n == name) return m;
  return std::nullopt;
}

}  // namespace navaid
