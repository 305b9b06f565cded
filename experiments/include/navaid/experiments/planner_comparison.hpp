#pragma once
// Local planners side by side on one map (the Smart Cane Table I protocol): start / goal pairs
// drawn from a seed among the places where the user fits, every planner run on every pair, and
// per planner the average, standard deviation and maximum of search time, nodes expanded and path
// length over the pairs every planner solved.
#include <cstdint>
#include <string>
#include <vector>

#include "navaid/mapping/esdf_2d.hpp"
#include "navaid/planning/local_planner.hpp"

namespace navaid::experiments {

struct PlannerPair {
  planning::PlanarPose start;
  mapping::Vec2 goal = mapping::Vec2::Zero();
};

struct PairSampling {
  std::size_t pairs = 30;
  std::uint64_t seed = 1;
  double clearance_m = 0.35;        ///< start and goal at least this far from obstacles (ESDF)
  double min_distance_m = 10.0;     ///< straight start-goal distance at least this
  std::size_t max_attempts = 100000;
};

/// Pairs whose start and goal are free with the clearance and far enough apart, and which the
/// `reference` planner connects (so that every pair has a path); deterministic for a seed. Throws
/// navaid::Error when max_attempts draws give fewer pairs.
std::vector<PlannerPair> sample_planner_pairs(const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                                              const planning::LocalPlanner& reference, const PairSampling& sampling);

/// One planner's result on one pair.
struct PlannerRun {
  bool found = false;
  double time_s = 0.0;
  std::size_t expanded = 0;
  double length_m = 0.0;
  std::string reason;
};

/// runs[planner][pair].
std::vector<std::vector<PlannerRun>> run_planners(const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                                                  const std::vector<const planning::LocalPlanner*>& planners,
                                                  const std::vector<PlannerPair>& pairs);

struct Summary3 {
  double avg = 0.0, std = 0.0, max = 0.0;
};
/// Average, sample standard deviation and maximum (n >= 1; std 0 for n = 1).
Summary3 summarize(const std::vector<double>& values);

}  // namespace navaid::experiments
