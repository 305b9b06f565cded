#include "navaid/evaluation/absolute_trajectory_error.hpp"

#include <cmath>

#include "navaid/core/errors.hpp"

namespace navaid::evaluation {

AteResult compute_ate(const std::vector<PosePair>& pairs, const AteOptions& options) {
  if (pairs.empty()) throw Error("ATE: no matched poses");
  AteResult r;
  r.alignment = options.alignment;
  r.align_frames = options.align_frames == 0 ? pairs.size() : options.align_frames;
  r.transform = align_trajectory(pairs, options.alignment, options.align_frames);
  r.aligned.reserve(pairs.size());
  r.position_errors.reserve(pairs.size());
  r.rotation_errors_rad.reserve(pairs.size());
  std::vector<double> rotation_deg;
  rotation_deg.reserve(pairs.size());
  for (const PosePair& p : pairs) {
    const SE3 aligned = r.transform.apply(p.est);
    r.aligned.push_back(aligned);
    r.position_errors.push_back((p.gt.t - aligned.t).norm());
    const double angle = p.gt.q.angularDistance(aligned.q);
    r.rotation_errors_rad.push_back(angle);
    rotation_deg.push_back(angle * 180.0 / M_PI);
  }
  r.position = compute_statistics(r.position_errors);
  r.rotation_deg = compute_statistics(rotation_deg);
  return r;
}

}  // namespace navaid::evaluation
