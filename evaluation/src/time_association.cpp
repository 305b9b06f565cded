#include "navaid/evaluation/time_association.hpp"

#include <algorithm>
#include <string>
#include <tuple>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {
namespace {

void require_sorted(const std::vector<Timestamp>& times, const char* what) {
  const auto it = std::is_sorted_until(times.begin(), times.end());
  if (it != times.end())
    throw Error(std::string("time association: ") + what + " times decrease at index " +
                std::to_string(it - times.begin()));
}

}  // namespace

std::vector<TimeMatch> associate_by_time(const std::vector<Timestamp>& est, const std::vector<Timestamp>& gt,
                                         Duration tolerance) {
  if (tolerance <= 0) throw Error("time association: the tolerance must be positive, got " + std::to_string(tolerance) + " ns");
  require_sorted(est, "estimate");
  require_sorted(gt, "ground-truth");

  // Candidates (|dt|, est, gt) within the open tolerance window, found by binary search, then the
  // greedy closest-first assignment: the all-pairs rule of rpg/TUM's associate.py in O(n log n).
  std::vector<std::tuple<Duration, std::size_t, std::size_t>> candidates;
  for (std::size_t i = 0; i < est.size(); ++i) {
    auto j = static_cast<std::size_t>(std::upper_bound(gt.begin(), gt.end(), est[i] - tolerance) - gt.begin());
    for (; j < gt.size() && gt[j] < est[i] + tolerance; ++j) {
      const Duration dt = gt[j] > est[i] ? gt[j] - est[i] : est[i] - gt[j];
      candidates.emplace_back(dt, i, j);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<bool> est_used(est.size(), false), gt_used(gt.size(), false);
  std::vector<TimeMatch> matches;
  for (const auto& [dt, i, j] : candidates) {
    if (est_used[i] || gt_used[j]) continue;
    est_used[i] = gt_used[j] = true;
    matches.push_back({i, j});
  }
  std::sort(matches.begin(), matches.end(), [](const TimeMatch& a, const TimeMatch& b) { return a.est < b.est; });
  return matches;
}

std::vector<PosePair> associate_poses(const std::vector<io::StampedPose>& est, const std::vector<io::StampedPose>& gt,
                                      Duration tolerance) {
  std::vector<Timestamp> te, tg;
  te.reserve(est.size());
  tg.reserve(gt.size());
  for (const auto& p : est) te.push_back(p.t);
  for (const auto& p : gt) tg.push_back(p.t);
  std::vector<PosePair> pairs;
  for (const TimeMatch& m : associate_by_time(te, tg, tolerance))
    pairs.push_back({est[m.est].t, gt[m.gt].t, est[m.est].T_W_B, gt[m.gt].T_W_B});
  return pairs;
}

}  // namespace navaid::evaluation
