#include "navaid/evaluation/evo_conventions.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {
namespace {

void require_sorted(const std::vector<io::StampedPose>& poses, const char* name) {
  for (std::size_t i = 1; i < poses.size(); ++i)
    if (poses[i].t < poses[i - 1].t) throw Error(std::string("evo association: the ") + name + " times decrease");
}

double angle_between(const SE3& a, const SE3& b) { return a.q.angularDistance(b.q); }

IndexPairs consecutive(const std::vector<std::size_t>& ids) {
  IndexPairs pairs;
  for (std::size_t k = 1; k < ids.size(); ++k) pairs.emplace_back(ids[k - 1], ids[k]);
  return pairs;
}

IndexPairs pairs_by_index(std::size_t n, std::size_t delta, bool all_pairs) {
  IndexPairs pairs;
  if (all_pairs) {
    for (std::size_t i = 0; i + delta < n; ++i) pairs.emplace_back(i, i + delta);
    return pairs;
  }
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < n; i += delta) ids.push_back(i);
  return consecutive(ids);
}

IndexPairs pairs_by_path(const std::vector<SE3>& poses, double delta, double tol, bool all_pairs) {
  if (!all_pairs) {
    std::vector<std::size_t> ids;
    double path = 0.0;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      if (i > 0) path += (poses[i].t - poses[i - 1].t).norm();
      if (path >= delta) {
        ids.push_back(i);
        path = 0.0;
      }
    }
    return consecutive(ids);
  }
  std::vector<double> distance(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i) distance[i] = distance[i - 1] + (poses[i].t - poses[i - 1].t).norm();
  IndexPairs pairs;
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    std::size_t best = i + 1;
    for (std::size_t j = i + 1; j < poses.size(); ++j)  // the first of equally near ones, as argmin
      if (std::abs(distance[j] - distance[i] - delta) < std::abs(distance[best] - distance[i] - delta)) best = j;
    if (std::abs(distance[best] - distance[i] - delta) <= tol) pairs.emplace_back(i, best);
  }
  return pairs;
}

IndexPairs pairs_by_angle(const std::vector<SE3>& poses, double delta, double tol, bool all_pairs) {
  IndexPairs pairs;
  if (all_pairs) {
    for (std::size_t i = 0; i + 1 < poses.size(); ++i)
      for (std::size_t j = i + 1; j < poses.size(); ++j) {
        const double a = angle_between(poses[i], poses[j]);
        if (delta - tol <= a && a <= delta + tol) pairs.emplace_back(i, j);
      }
    return pairs;
  }
  double accumulated = 0.0;
  std::size_t start = 0;
  for (std::size_t i = 0; i + 1 < poses.size(); ++i) {
    accumulated += angle_between(poses[i], poses[i + 1]);
    if (accumulated >= delta) {
      pairs.emplace_back(start, i + 1);
      accumulated = 0.0;
      start = i + 1;
    }
  }
  return pairs;
}

}  // namespace

std::vector<PosePair> associate_poses_evo(const std::vector<io::StampedPose>& est,
                                          const std::vector<io::StampedPose>& gt, Duration max_diff) {
  if (max_diff <= 0) throw Error("evo association: --t_max_diff must be positive");
  require_sorted(est, "estimate");
  require_sorted(gt, "ground-truth");
  // evo_ape associates (reference, estimate): the estimate is the shorter one on a tie.
  const bool walk_gt = est.size() > gt.size();
  const auto& walked = walk_gt ? gt : est;
  const auto& other = walk_gt ? est : gt;
  std::vector<PosePair> pairs;
  if (other.empty()) return pairs;
  std::size_t j = 0;
  for (const auto& p : walked) {
    // The nearest of a sorted list: advance while the next one is strictly nearer (argmin's first).
    while (j + 1 < other.size() && std::llabs(other[j + 1].t - p.t) < std::llabs(other[j].t - p.t)) ++j;
    // A later stamp of `walked` can only move the nearest forward, but an equal-distance earlier
    // pose must win: step back over ties.
    while (j > 0 && std::llabs(other[j - 1].t - p.t) <= std::llabs(other[j].t - p.t)) --j;
    if (std::llabs(other[j].t - p.t) > max_diff) continue;
    const auto& e = walk_gt ? other[j] : p;
    const auto& g = walk_gt ? p : other[j];
    pairs.push_back({e.t, g.t, e.T_W_B, g.T_W_B});
  }
  return pairs;
}

std::optional<RpeDeltaUnit> rpe_delta_unit_from_string(std::string_view name) {
  if (name == "f") return RpeDeltaUnit::kFrames;
  if (name == "m") return RpeDeltaUnit::kMeters;
  if (name == "d") return RpeDeltaUnit::kDegrees;
  if (name == "r") return RpeDeltaUnit::kRadians;
  return std::nullopt;
}

std::string_view to_string(RpeDeltaUnit unit) {
  switch (unit) {
    case RpeDeltaUnit::kFrames: return "frames";
    case RpeDeltaUnit::kMeters: return "m";
    case RpeDeltaUnit::kDegrees: return "deg";
    case RpeDeltaUnit::kRadians: return "rad";
  }
  return "?";
}

IndexPairs evo_rpe_pairs(const std::vector<SE3>& poses, const EvoRpeOptions& o) {
  if (!(o.delta > 0.0) || !std::isfinite(o.delta)) throw Error("RPE: --delta must be positive");
  if (!(o.rel_delta_tol >= 0.0)) throw Error("RPE: the relative delta tolerance must be >= 0");
  const double tol = o.rel_delta_tol * o.delta;
  IndexPairs pairs;
  switch (o.unit) {
    case RpeDeltaUnit::kFrames: {
      if (o.delta != std::floor(o.delta)) throw Error("RPE: a delta in frames must be a whole number");
      pairs = pairs_by_index(poses.size(), static_cast<std::size_t>(o.delta), o.all_pairs);
      break;
    }
    case RpeDeltaUnit::kMeters:
      pairs = pairs_by_path(poses, o.delta, tol, o.all_pairs);
      break;
    case RpeDeltaUnit::kDegrees:
    case RpeDeltaUnit::kRadians: {
      const double to_rad = o.unit == RpeDeltaUnit::kDegrees ? M_PI / 180.0 : 1.0;
      if (o.delta * to_rad > M_PI) throw Error("RPE: a delta angle must be within [0, 180] degrees / [0, pi]");
      pairs = pairs_by_angle(poses, o.delta * to_rad, tol * to_rad, o.all_pairs);
      break;
    }
  }
  if (pairs.empty())
    throw Error("RPE: delta = " + std::to_string(o.delta) + " (" + std::string(to_string(o.unit)) +
                ") gives no pair over " + std::to_string(poses.size()) +
                " poses; try a smaller delta or a looser tolerance");
  return pairs;
}

EvoRpeResult compute_rpe_evo(const std::vector<PosePair>& pairs, const std::vector<SE3>& aligned_est,
                             const EvoRpeOptions& options) {
  if (pairs.size() != aligned_est.size()) throw Error("RPE: one aligned estimate per matched pair is needed");
  std::vector<SE3> reference;
  reference.reserve(pairs.size());
  for (const auto& p : pairs) reference.push_back(p.gt);
  EvoRpeResult r;
  r.options = options;
  r.pairs = evo_rpe_pairs(options.pairs_from_reference ? reference : aligned_est, options);
  std::vector<double> rotation_deg;
  for (const auto& [i, j] : r.pairs) {
    const SE3 E = (reference[i].inverse() * reference[j]).inverse() * (aligned_est[i].inverse() * aligned_est[j]);
    r.translation_errors.push_back(E.t.norm());
    r.rotation_errors_rad.push_back(E.q.angularDistance(Quat::Identity()));
    rotation_deg.push_back(r.rotation_errors_rad.back() * 180.0 / M_PI);
  }
  r.translation = compute_statistics(r.translation_errors);
  r.rotation_deg = compute_statistics(rotation_deg);
  return r;
}

}  // namespace navaid::evaluation
