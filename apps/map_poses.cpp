#include "map_poses.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/start_alignment.hpp"

namespace navaid::cli {

FramePoses poses_from_estimates(const std::vector<RgbdFrame>& frames, const std::vector<StateEstimate>& estimates,
                                const std::filesystem::path& file) {
  FramePoses out(frames.size());
  if (frames.empty()) return out;
  if (estimates.empty()) throw IoError(file.string(), "holds no estimates");
  Timestamp period = 0;
  if (frames.size() > 1) period = (frames.back().t - frames.front().t) / static_cast<Timestamp>(frames.size() - 1);
  const Timestamp tolerance = std::max<Timestamp>(period / 2, 1);
  const Timestamp slack = std::max<Timestamp>(period, 1);
  if (estimates.front().t < frames.front().t - slack || estimates.back().t > frames.back().t + slack)
    throw IoError(file.string(), "does not match the recording: its estimates span " +
                                     std::to_string(estimates.front().t) + " .. " + std::to_string(estimates.back().t) +
                                     " ns, the frames " + std::to_string(frames.front().t) + " .. " +
                                     std::to_string(frames.back().t) + " ns");
  std::size_t paired = 0, j = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    while (j + 1 < estimates.size() && std::llabs(estimates[j + 1].t - frames[i].t) <= std::llabs(estimates[j].t - frames[i].t))
      ++j;
    if (std::llabs(estimates[j].t - frames[i].t) <= tolerance) {
      out[i] = estimates[j];
      ++paired;
    }
  }
  if (paired == 0 || 2 * paired < estimates.size())
    throw IoError(file.string(), "does not match the recording: " + std::to_string(paired) + " of its " +
                                     std::to_string(estimates.size()) + " estimates fall on one of the " +
                                     std::to_string(frames.size()) + " frames' times");
  return out;
}

FramePoses poses_from_groundtruth(const io::Recording& rec, const std::vector<RgbdFrame>& frames, double offset_s) {
  if (rec.groundtruth.empty()) throw Error(rec.path + ": no ground truth to take poses from (--poses groundtruth)");
  std::vector<io::StampedPose> gt;
  gt.reserve(rec.groundtruth.size());
  for (const auto& g : rec.groundtruth) gt.push_back({g.t, g.T_W_B});
  FramePoses out(frames.size());
  const Timestamp offset = static_cast<Timestamp>(std::llround(offset_s * 1e9));
  const double sigma_rot = 0.01 * M_PI / 180.0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Timestamp t = frames[i].t + offset;
    if (t < gt.front().t || t > gt.back().t) continue;
    StateEstimate e;
    e.t = frames[i].t;
    e.T_W_B = evaluation::interpolate_pose(gt, t);
    e.mode = EstimatorMode::kRgbdVio;
    e.covariance = Mat15::Identity() * 1e-6;
    e.covariance.block<3, 3>(0, 0) = Mat3::Identity() * sigma_rot * sigma_rot;
    out[i] = e;
  }
  return out;
}

}  // namespace navaid::cli
