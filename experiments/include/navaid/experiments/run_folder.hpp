#pragma once
// Reading back what `navaid run` wrote into a run folder: estimates.csv (state, the position and
// rotation covariance blocks, mode) and summary.json's "recording" (the recording it ran on).
#include <filesystem>
#include <vector>

#include "navaid/core/state_estimate.hpp"

namespace navaid::experiments {

/// estimates.csv as `navaid run` writes it (docs/estimator.md). Only the rotation and position
/// blocks of the covariance are stored: the rest of StateEstimate::covariance is left at identity,
/// the ENU registration unset. Throws IoError naming file:line on a missing column, bad number,
/// unknown mode, non-unit quaternion or times not strictly increasing.
std::vector<StateEstimate> read_estimates_csv(const std::filesystem::path& file);

/// summary.json's "recording" of a run folder. Throws IoError when the file is missing, is not
/// JSON, or has no "recording" string.
std::filesystem::path run_recording(const std::filesystem::path& run_folder);

}  // namespace navaid::experiments
