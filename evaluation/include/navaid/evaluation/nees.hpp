#pragma once
// Normalized estimation error squared (NEES) of positions and orientations, and the chi-square test
// of filter consistency (Bar-Shalom, Li & Kirubarajan, "Estimation with Applications to Tracking and
// Navigation", sec. 5.4). For an error e of dimension d with covariance P, NEES = e^T P^-1 e is
// chi2(d) distributed when the estimator is consistent; the average of N independent NEES values,
// times N, is chi2(N d). Hence the two-sided bounds for the average (ANEES) at confidence c are
//   [chi2_quantile((1-c)/2, N d) / N, chi2_quantile((1+c)/2, N d) / N].
// Errors, in the parametrization of StateEstimate::covariance:
//   position     e_p = p_gt - p_est (world frame)                 [m]
//   orientation  e_theta = Log(R_est^T R_gt), R_gt = R_est Exp(e) [rad] (right perturbation)
// NEES is taken in the frame both trajectories share (simulation, where the estimator's W is the
// ground truth's W); no alignment is applied. Values over time of one run are correlated, so the
// bounds are exact for averages over independent Monte-Carlo runs and indicative over time.
#include <vector>

#include "navaid/core/geometry.hpp"
#include "navaid/core/state_estimate.hpp"
#include "navaid/core/time.hpp"
#include "navaid/evaluation/time_association.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

/// One pose estimate with the 3x3 covariances the NEES needs.
struct PoseWithCovariance {
  Timestamp t = 0;
  SE3 T_W_B;
  Mat3 position_covariance = Mat3::Identity();  ///< of e_p [m^2]
  Mat3 rotation_covariance = Mat3::Identity();  ///< of e_theta [rad^2]
};

/// The pose and the two 3x3 diagonal blocks of StateEstimate::covariance.
PoseWithCovariance pose_with_covariance(const StateEstimate& estimate);

/// e^T P^-1 e. Throws navaid::Error when P is not symmetric positive definite or not finite.
double nees(const Vec3& error, const Mat3& covariance);

/// Per-pose NEES against ground truth poses (same length, same order; navaid::Error otherwise).
std::vector<double> position_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth);
std::vector<double> orientation_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth);

struct NeesSummary {
  std::size_t count = 0;
  int dof = 3;
  double confidence = 0.95;
  double average = 0.0;  ///< ANEES
  double lower = 0.0;    ///< two-sided bounds of ANEES for a consistent estimator
  double upper = 0.0;
  double sample_lower = 0.0;  ///< two-sided bounds of a single NEES value, chi2(dof)
  double sample_upper = 0.0;
  double fraction_inside = 0.0;  ///< of the values within [sample_lower, sample_upper] (expect ~confidence)
  bool consistent() const { return average >= lower && average <= upper; }
};

/// Summary of independent NEES values: those of M Monte-Carlo runs at one time step, or (indicative)
/// one run's values over time. Throws navaid::Error on no values, a negative or non-finite value, dof < 1 or confidence
/// outside (0, 1).
NeesSummary summarize_nees(const std::vector<double>& values, int dof, double confidence = 0.95);

/// Position and orientation NEES of an estimator's output against ground truth, matched by time
/// (time_association.hpp); summaries as summarize_nees with dof 3. Throws navaid::Error when
/// nothing matches and on the errors above.
struct NeesEvaluation {
  std::vector<Timestamp> t;  ///< estimate times of the matched poses
  std::vector<double> position, orientation;
  NeesSummary position_summary, orientation_summary;
};
NeesEvaluation evaluate_nees(const std::vector<PoseWithCovariance>& estimates, const std::vector<io::StampedPose>& truth,
                             double confidence = 0.95, Duration tolerance = kDefaultAssociationTolerance);

/// NEES of estimates paired with their true poses (same length), taken at times t, summarized with
/// the 3-dof chi-square bounds at `confidence`.
NeesEvaluation nees_of_pairs(const std::vector<PoseWithCovariance>& estimates, const std::vector<SE3>& truth,
                             std::vector<Timestamp> t, double confidence);

}  // namespace navaid::evaluation
