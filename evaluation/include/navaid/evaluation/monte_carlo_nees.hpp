#pragma once
// Monte-Carlo consistency of an estimator (Bar-Shalom, Li & Kirubarajan, "Estimation with
// Applications to Tracking and Navigation", sec. 5.4.2): N runs of the same recording with
// independent noise seeds share their epochs (frame time stamps). At epoch k the average NEES over
// the runs, ANEES_k = (1/N) sum_i eps_ik, satisfies N ANEES_k ~ chi2(N d) for a consistent
// estimator (the runs are independent), which gives the two-sided per-epoch bounds
//   [chi2_quantile(a/2, N d) / N, chi2_quantile(1 - a/2, N d) / N],   a = 1 - confidence,
// and about `confidence` of the epochs should lie inside them.
//
// The time average ANEES = (1/K) sum_k ANEES_k is harder: the K epochs of one run are correlated
// (the error drifts slowly), so N K ANEES is NOT chi2(N K d); those bounds are far too narrow and
// are reported for reference only. The verdict uses the conservative bounds, which treat each run's
// time average as one chi2(d)-like sample (fully correlated epochs): chi2(N d) / N, numerically the
// per-epoch bounds. Between the two, the effective number of independent epochs per run K_eff is
// moment-matched to the spread of the N per-run averages (a scaled chi2 with K_eff d dof has
// variance 2 mean^2 / (K_eff d), whatever the scale), giving indicative bounds chi2(N K_eff d).
//
// The per-run NEES series are those of first_state_nees (start_alignment.hpp), as `navaid run`
// reports them in summary.json.
#include <string>
#include <vector>

#include "navaid/core/state_estimate.hpp"
#include "navaid/core/time.hpp"
#include "navaid/io/tum_trajectory.hpp"

namespace navaid::evaluation {

/// One run's NEES over time.
struct NeesSeries {
  std::string name;           ///< names the run in error messages (its folder)
  std::vector<Timestamp> t;   ///< strictly increasing
  std::vector<double> position, orientation;  ///< NEES (dof 3 each) at t
};

/// The NEES series `navaid run` reports on: estimates aligned to the ground truth at their first
/// state (align_to_first_state), then first_state_nees. Throws navaid::Error when nothing is left.
NeesSeries first_state_nees_series(std::string name, const std::vector<StateEstimate>& estimates,
                                   const std::vector<io::StampedPose>& groundtruth);

/// Two-sided bounds of an average of NEES values.
struct NeesBounds {
  double dof = 0;  ///< of the chi-square the bounds come from (the sum of the averaged values)
  double lower = 0, upper = 0;
  bool contains(double x) const { return x >= lower && x <= upper; }
};

/// chi2(dof) quantiles / `samples`: the bounds of the average of `samples` values whose sum is
/// chi2(dof). Throws navaid::Error for samples or dof not positive, confidence outside (0, 1).
NeesBounds average_nees_bounds(double dof, double samples, double confidence);

/// ANEES statistics of one quantity (position or orientation) over N runs x K epochs.
struct AneesStatistics {
  int dof = 3;
  double confidence = 0.95;
  std::size_t runs = 0, epochs = 0;
  std::vector<double> anees;  ///< per epoch, ANEES_k
  NeesBounds epoch_bounds;    ///< of each ANEES_k: chi2(N d) / N
  double fraction_inside = 0; ///< of the epochs with ANEES_k inside epoch_bounds (expect ~confidence)
  std::size_t epochs_below = 0, epochs_above = 0;
  double time_average = 0;           ///< (1/K) sum_k ANEES_k
  std::vector<double> run_averages;  ///< each run's time average
  NeesBounds conservative_bounds;    ///< of time_average, fully correlated epochs: chi2(N d) / N
  NeesBounds independent_bounds;     ///< of time_average, independent epochs: chi2(N K d) / (N K)
  double effective_epochs = 0;       ///< K_eff in [1, K], from the spread of run_averages
  NeesBounds effective_bounds;       ///< chi2(N K_eff d) / (N K_eff)
  /// The verdict: time_average inside conservative_bounds.
  bool consistent() const { return conservative_bounds.contains(time_average); }
};

/// values[i][k] = NEES of run i at epoch k (all runs the same length K >= 1, N >= 2 runs, every
/// value finite and >= 0). Throws navaid::Error otherwise, and for dof < 1 or a bad confidence.
AneesStatistics anees_statistics(const std::vector<std::vector<double>>& values, int dof, double confidence = 0.95);

/// Position and orientation statistics over the epochs all runs share.
struct MonteCarloNees {
  std::vector<Timestamp> t;           ///< the shared epochs
  std::vector<std::string> runs;      ///< the runs' names, in input order
  std::vector<std::size_t> dropped;   ///< per run, its epochs outside the shared span
  AneesStatistics position, orientation;
};

/// Runs may start (initialize) and end at different epochs: the shared span is from the latest
/// first epoch to the earliest last epoch, and inside it every run must have exactly the same time
/// stamps (the same recording's frames). `skip` more is left out at the start of the span (the
/// first-state NEES is ~0 right after the first state, whose error is zero by construction).
/// Throws navaid::Error naming the run and the time stamp when they differ, when the runs share no
/// epoch (after the skip), for fewer than 2 runs, a run with unequal lengths, times not strictly
/// increasing, a negative skip, or a negative or non-finite NEES.
MonteCarloNees monte_carlo_nees(const std::vector<NeesSeries>& runs, double confidence = 0.95, Duration skip = 0);

}  // namespace navaid::evaluation
