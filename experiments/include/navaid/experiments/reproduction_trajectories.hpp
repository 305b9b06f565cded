#pragma once
// The data of a reproduction's trajectory figure: several methods' estimates of one recording,
// each aligned onto the ground truth (4-DOF, as the ATE), in one CSV for
// experiments/figures/plot_reproduction_trajectories.py.
#include <filesystem>
#include <string>
#include <vector>

namespace navaid::experiments {

struct MethodTrajectory {
  std::string method;
  std::filesystem::path trajectory;  ///< TUM file of the estimate
};

/// Writes `csv` with columns method,t,x,y,z: the ground truth first (method "ground truth",
/// thinned to one pose per 10 ms), then each method's aligned positions. Returns each method's
/// ATE RMSE [m] in the given order. Throws IoError on unreadable files and navaid::Error when an
/// estimate does not overlap the ground truth in time.
std::vector<double> write_aligned_trajectories(const std::filesystem::path& groundtruth_tum,
                                               const std::vector<MethodTrajectory>& methods,
                                               const std::filesystem::path& csv);

}  // namespace navaid::experiments
