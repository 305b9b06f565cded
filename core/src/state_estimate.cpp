#include "navaid/core/state_estimate.hpp"

#include "navaid/core/enum_names.hpp"

namespace navaid {
namespace {
constexpr NameTable<EstimatorMode, 5> kModeNames{{
    {EstimatorMode::kInitializing, "initializing"},
    {EstimatorMode::kRgbdVio, "rgbd-vio"},
    {EstimatorMode::kVio, "vio"},
    {EstimatorMode::kImuOnly, "imu-only"},
    {EstimatorMode::kLost, "lost"},
}};
}  // namespace

std::string_view to_string(EstimatorMode mode) { return enum_name(kModeNames, mode); }

std::optional<EstimatorMode> estimator_mode_from_string(std::string_view name) { return enum_value(kModeNames, name); }

}  // namespace navaid
