#pragma once
// Where navaid map takes each frame's pose from: a navaid run folder's estimates (with their
// covariance and mode) or the recording's ground truth (mapping-only studies).
#include <filesystem>
#include <optional>
#include <vector>

#include "navaid/core/state_estimate.hpp"
#include "navaid/io/recording.hpp"

namespace navaid::cli {

/// One pose per frame of `frames` (nullopt: no estimate for that frame, e.g. before the first).
using FramePoses = std::vector<std::optional<StateEstimate>>;

/// Pairs each frame with the estimate of the same time stamp (within half the frame period, for
/// recordings whose frames are not on an exact grid). Throws IoError naming `estimates_file` when
/// the estimates do not belong to these frames: none pairs, or fewer than half of them do, or they
/// start or end outside the frames' time span.
FramePoses poses_from_estimates(const std::vector<RgbdFrame>& frames, const std::vector<StateEstimate>& estimates,
                                const std::filesystem::path& estimates_file);

/// The ground-truth body pose at each frame's time in the IMU clock (t + camera time offset),
/// interpolated (linear position, slerp rotation) between the bracketing samples; mode rgbd-vio
/// with a 1 mm / 0.01 deg covariance. nullopt outside the ground truth's span. Throws Error when the
/// recording has no ground truth.
FramePoses poses_from_groundtruth(const io::Recording& recording, const std::vector<RgbdFrame>& frames,
                                  double camera_time_offset_s);

}  // namespace navaid::cli
