#include "navaid/evaluation/nees.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <string>
#include <utility>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/chi_square.hpp"

namespace navaid::evaluation {
namespace {

void require_same_length(std::size_t a, std::size_t b) {
  if (a != b)
    throw Error("NEES: " + std::to_string(a) + " estimates but " + std::to_string(b) + " ground-truth poses");
}

}  // namespace

PoseWithCovariance pose_with_covariance(const StateEstimate& estimate) {
  PoseWithCovariance p;
  p.t = estimate.t;
  p.T_W_B = estimate.T_W_B;
  p.rotation_covariance = estimate.covariance.block<3, 3>(0, 0);
  p.position_covariance = estimate.covariance.block<3, 3>(3, 3);
  return p;
}

double nees(const Vec3& error, const Mat3& covariance) {
  if (!error.allFinite() || !covariance.allFinite()) throw Error("NEES: error or covariance not finite");
  if (!covariance.isApprox(covariance.transpose(), 1e-9))
    throw Error("NEES: covariance is not symmetric");
  const Eigen::LLT<Mat3> llt(covariance);
  if (llt.info() != Eigen::Success) throw Error("NEES: covariance is not positive definite");
  return error.dot(llt.solve(error));
}

std::vector<double> position_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth) {
  require_same_length(estimates.size(), truth.size());
  std::vector<double> out;
  out.reserve(estimates.size());
  for (std::size_t i = 0; i < estimates.size(); ++i)
    out.push_back(nees(truth[i].t - estimates[i].T_W_B.t, estimates[i].position_covariance));
  return out;
}

std::vector<double> orientation_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth) {
  require_same_length(estimates.size(), truth.size());
  std::vector<double> out;
  out.reserve(estimates.size());
  for (std::size_t i = 0; i < estimates.size(); ++i)
    out.push_back(nees(so3_boxminus(truth[i].q, estimates[i].T_W_B.q), estimates[i].rotation_covariance));
  return out;
}

NeesSummary summarize_nees(const std::vector<double>& values, int dof, double confidence) {
  if (values.empty()) throw Error("NEES summary: no values");
  if (dof < 1) throw Error("NEES summary: dof must be at least 1, got " + std::to_string(dof));
  if (!(confidence > 0.0 && confidence < 1.0))
    throw Error("NEES summary: confidence must be in (0, 1), got " + std::to_string(confidence));
  NeesSummary s;
  s.count = values.size();
  s.dof = dof;
  s.confidence = confidence;
  const double alpha = 1.0 - confidence;
  s.sample_lower = chi_square_quantile(0.5 * alpha, dof);
  s.sample_upper = chi_square_quantile(1.0 - 0.5 * alpha, dof);
  double sum = 0.0;
  std::size_t inside = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(values[i] >= 0.0) || !std::isfinite(values[i]))
      throw Error("NEES summary: value " + std::to_string(i) + " is negative or not finite");
    sum += values[i];
    inside += values[i] >= s.sample_lower && values[i] <= s.sample_upper;
  }
  const double n = static_cast<double>(values.size());
  s.average = sum / n;
  s.fraction_inside = static_cast<double>(inside) / n;
  s.lower = chi_square_quantile(0.5 * alpha, n * dof) / n;
  s.upper = chi_square_quantile(1.0 - 0.5 * alpha, n * dof) / n;
  return s;
}

NeesEvaluation evaluate_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<io::StampedPose>& truth,
                             double confidence, Duration tolerance) {
  std::vector<Timestamp> te, tg;
  for (const auto& e : estimates) te.push_back(e.t);
  for (const auto& g : truth) tg.push_back(g.t);
  const std::vector<TimeMatch> matches = associate_by_time(te, tg, tolerance);
  if (matches.empty()) throw Error("NEES: no estimate is within the tolerance of a ground-truth pose");
  std::vector<PoseWithCovariance> matched_est;
  std::vector<SE3> matched_gt;
  std::vector<Timestamp> t;
  for (const TimeMatch& m : matches) {
    matched_est.push_back(estimates[m.est]);
    matched_gt.push_back(truth[m.gt].T_W_B);
    t.push_back(estimates[m.est].t);
  }
  return nees_of_pairs(matched_est, matched_gt, std::move(t), confidence);
}

NeesEvaluation nees_of_pairs(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth,
                             std::vector<Timestamp> t, double confidence) {
  NeesEvaluation r;
  r.t = std::move(t);
  r.position = position_nees(estimates, truth);
  r.orientation = orientation_nees(estimates, truth);
  r.position_summary = summarize_nees(r.position, 3, confidence);
  r.orientation_summary = summarize_nees(r.orientation, 3, confidence);
  return r;
}

}  // namespace navaid::evaluation
