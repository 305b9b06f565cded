#include "navaid/evaluation/relative_pose_error.hpp"

#include <cmath>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {

std::vector<double> cumulative_path_length(const std::vector<Vec3>& positions) {
  std::vector<double> d;
  d.reserve(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    d.push_back(i == 0 ? 0.0 : d.back() + (positions[i] - positions[i - 1]).norm());
  return d;
}

RpeResult compute_rpe(const std::vector<PosePair>& pairs, double length_m, double scale, double max_length_error) {
  if (!(length_m > 0.0) || !std::isfinite(length_m))
    throw Error("RPE: the sub-trajectory length must be positive, got " + std::to_string(length_m));
  if (!(scale > 0.0) || !std::isfinite(scale)) throw Error("RPE: the scale must be positive, got " + std::to_string(scale));
  if (max_length_error < 0.0) max_length_error = 0.2 * length_m;

  RpeResult r;
  r.length_m = length_m;
  std::vector<Vec3> gt_positions;
  gt_positions.reserve(pairs.size());
  for (const auto& p : pairs) gt_positions.push_back(p.gt.t);
  const std::vector<double> dist = cumulative_path_length(gt_positions);

  std::vector<double> percent, rotation_deg;
  std::size_t j = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    // dist is non-decreasing, so |dist[j] - target| is minimised where dist crosses the target and
    // the best end only moves forward with i.
    const double target = dist[i] + length_m;
    if (j < i) j = i;
    while (j + 1 < pairs.size() && std::abs(dist[j + 1] - target) <= std::abs(dist[j] - target)) ++j;
    // rpg keeps the first of equally close candidates; skip forward over ties only when strictly better.
    std::size_t best = j;
    while (best > i && std::abs(dist[best - 1] - target) == std::abs(dist[best] - target)) --best;
    if (!(std::abs(dist[best] - target) < max_length_error)) continue;
    const PosePair& a = pairs[i];
    const PosePair& b = pairs[best];
    SE3 est_rel = a.est.inverse() * b.est;
    est_rel.t *= scale;
    const SE3 error = (a.gt.inverse() * b.gt).inverse() * est_rel;
    r.start.push_back(i);
    r.end.push_back(best);
    r.translation_errors.push_back(error.t.norm());
    r.rotation_errors_rad.push_back(error.q.angularDistance(Quat::Identity()));
    percent.push_back(100.0 * r.translation_errors.back() / length_m);
    rotation_deg.push_back(r.rotation_errors_rad.back() * 180.0 / M_PI);
  }
  if (!r.empty()) {
    r.translation = compute_statistics(r.translation_errors);
    r.translation_percent = compute_statistics(percent);
    r.rotation_deg = compute_statistics(rotation_deg);
  }
  return r;
}

std::vector<double> lengths_from_percentages(double path_length_m, const std::vector<double>& percentages) {
  std::vector<double> lengths;
  for (const double pct : percentages) {
    if (!(pct > 0.0 && pct <= 100.0))
      throw Error("RPE: a length percentage must be in (0, 100], got " + std::to_string(pct));
    lengths.push_back(std::trunc(pct / 100.0 * path_length_m * 100.0) / 100.0);
  }
  return lengths;
}

}  // namespace navaid::evaluation
