#include "navaid/evaluation/monte_carlo_nees.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "navaid/core/errors.hpp"
#include "navaid/evaluation/chi_square.hpp"
#include "navaid/evaluation/start_alignment.hpp"

namespace navaid::evaluation {
namespace {

void check_series(const NeesSeries& run) {
  if (run.t.empty()) throw Error("Monte-Carlo NEES: run '" + run.name + "' has no epochs");
  if (run.position.size() != run.t.size() || run.orientation.size() != run.t.size())
    throw Error(fmt::format("Monte-Carlo NEES: run '{}' has {} epochs but {} position and {} orientation values",
                            run.name, run.t.size(), run.position.size(), run.orientation.size()));
  for (std::size_t k = 1; k < run.t.size(); ++k)
    if (run.t[k] <= run.t[k - 1])
      throw Error(fmt::format("Monte-Carlo NEES: run '{}': epoch times not strictly increasing at {} s", run.name,
                              format_seconds(run.t[k])));
}

}  // namespace

NeesSeries first_state_nees_series(std::string name, const std::vector<StateEstimate>& estimates,
                                   const std::vector<io::StampedPose>& groundtruth) {
  const auto aligned = align_to_first_state(estimates, groundtruth);
  if (aligned.empty())
    throw Error("run '" + name + "': no estimate past initialization within the ground truth's time span");
  NeesEvaluation e = first_state_nees(aligned, groundtruth);
  return {std::move(name), std::move(e.t), std::move(e.position), std::move(e.orientation)};
}

NeesBounds average_nees_bounds(double dof, double samples, double confidence) {
  if (!(dof > 0.0) || !(samples > 0.0) || !std::isfinite(dof) || !std::isfinite(samples))
    throw Error(fmt::format("NEES bounds: dof ({}) and sample count ({}) must be positive", dof, samples));
  if (!(confidence > 0.0 && confidence < 1.0))
    throw Error(fmt::format("NEES bounds: confidence must be in (0, 1), got {}", confidence));
  const double alpha = 1.0 - confidence;
  return {dof, chi_square_quantile(0.5 * alpha, dof) / samples, chi_square_quantile(1.0 - 0.5 * alpha, dof) / samples};
}

AneesStatistics anees_statistics(const std::vector<std::vector<double>>& values, int dof, double confidence) {
  if (values.size() < 2)
    throw Error(fmt::format("Monte-Carlo NEES: needs at least 2 runs, got {}", values.size()));
  if (dof < 1) throw Error(fmt::format("Monte-Carlo NEES: dof must be at least 1, got {}", dof));
  const std::size_t K = values.front().size();
  if (K == 0) throw Error("Monte-Carlo NEES: no epochs");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i].size() != K)
      throw Error(fmt::format("Monte-Carlo NEES: run {} has {} epochs, run 0 has {}", i, values[i].size(), K));
    for (std::size_t k = 0; k < K; ++k)
      if (!(values[i][k] >= 0.0) || !std::isfinite(values[i][k]))
        throw Error(fmt::format("Monte-Carlo NEES: run {} epoch {}: NEES {} is negative or not finite", i, k,
                                values[i][k]));
  }
  AneesStatistics s;
  s.dof = dof;
  s.confidence = confidence;
  s.runs = values.size();
  s.epochs = K;
  const double N = static_cast<double>(s.runs), Kd = static_cast<double>(K), d = dof;
  s.epoch_bounds = average_nees_bounds(N * d, N, confidence);
  s.anees.assign(K, 0.0);
  s.run_averages.assign(s.runs, 0.0);
  for (std::size_t i = 0; i < s.runs; ++i)
    for (std::size_t k = 0; k < K; ++k) {
      s.anees[k] += values[i][k] / N;
      s.run_averages[i] += values[i][k] / Kd;
    }
  double sum = 0.0;
  for (double a : s.anees) {
    sum += a;
    s.epochs_below += a < s.epoch_bounds.lower;
    s.epochs_above += a > s.epoch_bounds.upper;
  }
  s.time_average = sum / Kd;
  s.fraction_inside = static_cast<double>(K - s.epochs_below - s.epochs_above) / Kd;
  s.conservative_bounds = s.epoch_bounds;
  s.independent_bounds = average_nees_bounds(N * Kd * d, N * Kd, confidence);

  // Moment matching: a run average that is (scale / K_eff) chi2(K_eff d) has
  // var / mean^2 = 2 / (K_eff d).
  double var = 0.0;
  for (double a : s.run_averages) var += (a - s.time_average) * (a - s.time_average);
  var /= N - 1.0;
  s.effective_epochs = var > 0.0 ? 2.0 * s.time_average * s.time_average / (d * var) : Kd;
  s.effective_epochs = std::clamp(s.effective_epochs, 1.0, Kd);
  s.effective_bounds = average_nees_bounds(N * s.effective_epochs * d, N * s.effective_epochs, confidence);
  return s;
}

MonteCarloNees monte_carlo_nees(const std::vector<NeesSeries>& runs, double confidence, Duration skip) {
  if (runs.size() < 2) throw Error(fmt::format("Monte-Carlo NEES: needs at least 2 runs, got {}", runs.size()));
  if (skip < 0) throw Error(fmt::format("Monte-Carlo NEES: skip must not be negative, got {} s", format_seconds(skip)));
  for (const auto& r : runs) check_series(r);
  Timestamp first = runs.front().t.front(), last = runs.front().t.back();
  for (const auto& r : runs) {
    first = std::max(first, r.t.front());
    last = std::min(last, r.t.back());
  }
  if (first > last) throw Error("Monte-Carlo NEES: the runs share no epoch (their time spans do not overlap)");
  first += skip;
  if (first > last)
    throw Error(fmt::format("Monte-Carlo NEES: no shared epoch is left after skipping {} s", format_seconds(skip)));

  MonteCarloNees m;
  const auto in_span = [&](const NeesSeries& r) {
    const auto b = std::lower_bound(r.t.begin(), r.t.end(), first);
    const auto e = std::upper_bound(r.t.begin(), r.t.end(), last);
    return std::make_pair(static_cast<std::size_t>(b - r.t.begin()), static_cast<std::size_t>(e - r.t.begin()));
  };
  const auto [b0, e0] = in_span(runs.front());
  m.t.assign(runs.front().t.begin() + static_cast<std::ptrdiff_t>(b0), runs.front().t.begin() + static_cast<std::ptrdiff_t>(e0));
  std::vector<std::vector<double>> pos, rot;
  for (const auto& r : runs) {
    const auto [b, e] = in_span(r);
    // Same epochs: equal counts and equal stamps. The earlier of two differing stamps is the one
    // the other run lacks.
    for (std::size_t k = 0; k < e - b || k < m.t.size(); ++k) {
      const bool mine = k < e - b, theirs = k < m.t.size();
      if (mine && theirs && r.t[b + k] == m.t[k]) continue;
      const bool extra_here = !theirs || (mine && r.t[b + k] < m.t[k]);
      throw Error(fmt::format(
          "Monte-Carlo NEES: runs '{}' and '{}' do not share their epochs: {} s is in '{}' only (runs must be the "
          "same recording with different seeds)",
          runs.front().name, r.name, format_seconds(extra_here ? r.t[b + k] : m.t[k]),
          extra_here ? r.name : runs.front().name));
    }
    m.runs.push_back(r.name);
    m.dropped.push_back(r.t.size() - (e - b));
    pos.emplace_back(r.position.begin() + static_cast<std::ptrdiff_t>(b), r.position.begin() + static_cast<std::ptrdiff_t>(e));
    rot.emplace_back(r.orientation.begin() + static_cast<std::ptrdiff_t>(b),
                     r.orientation.begin() + static_cast<std::ptrdiff_t>(e));
  }
  m.position = anees_statistics(pos, 3, confidence);
  m.orientation = anees_statistics(rot, 3, confidence);
  return m;
}

}  // namespace navaid::evaluation
