#include "navaid/experiments/reproduction_trajectories.hpp"

#include <fmt/format.h>

#include <fstream>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/absolute_trajectory_error.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::experiments {

std::vector<double> write_aligned_trajectories(const std::filesystem::path& groundtruth_tum,
                                               const std::vector<MethodTrajectory>& methods,
                                               const std::filesystem::path& csv) {
  const auto gt = io::read_tum_trajectory(groundtruth_tum);
  if (gt.empty()) throw IoError(groundtruth_tum.string(), "holds no poses");
  const Timestamp t0 = gt.front().t;
  std::string text = "method,t,x,y,z\n";
  auto row = [&](const std::string& method, Timestamp t, const Vec3& p) {
    text += fmt::format("{},{:.4f},{:.5f},{:.5f},{:.5f}\n", method, ns_to_seconds(t - t0), p.x(), p.y(), p.z());
  };
  // A 500 Hz ground truth would dwarf the estimates in the file without changing the figure.
  constexpr Duration kGtSpacing = 10'000'000;
  Timestamp last = gt.front().t - kGtSpacing;
  for (const auto& pose : gt)
    if (pose.t - last >= kGtSpacing) {
      row("ground truth", pose.t, pose.T_W_B.t);
      last = pose.t;
    }
  std::vector<double> rmse;
  for (const auto& m : methods) {
    const auto est = io::read_tum_trajectory(m.trajectory);
    const auto pairs = evaluation::associate_poses(est, gt);
    if (pairs.empty()) throw Error(fmt::format("{}: no pose of {} matches the ground truth {} in time", m.method,
                                               m.trajectory.string(), groundtruth_tum.string()));
    const evaluation::AteResult ate = evaluation::compute_ate(pairs, {evaluation::AlignmentMode::kPosYaw, 0});
    for (std::size_t i = 0; i < pairs.size(); ++i) row(m.method, pairs[i].t_est, ate.aligned[i].t);
    rmse.push_back(ate.position.rmse);
  }
  std::ofstream out(csv, std::ios::binary);
  out << text;
  if (!out) throw IoError(csv.string(), "cannot write");
  return rmse;
}

}  // namespace navaid::experiments
