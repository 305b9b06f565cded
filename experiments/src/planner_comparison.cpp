#include "navaid/experiments/planner_comparison.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "navaid/core/errors.hpp"
#include "navaid/core/random_draws.hpp"

namespace navaid::experiments {

std::vector<PlannerPair> sample_planner_pairs(const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                                              const planning::LocalPlanner& reference, const PairSampling& sampling) {
  const mapping::GridGeometry& g = cost.geometry();
  const mapping::Vec2 lo = g.origin_W();
  const mapping::Vec2 size = mapping::Vec2(g.width(), g.height()) * g.resolution();
  std::mt19937_64 rng(sampling.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto draw_free = [&]() -> std::optional<mapping::Vec2> {
    const mapping::Vec2 p = lo + draw_vector<2>([&] { return unit(rng); }).cwiseProduct(size);
    const std::optional<double> d = esdf.distance(p);
    if (!d || *d < sampling.clearance_m) return std::nullopt;
    return p;
  };
  std::vector<PlannerPair> pairs;
  std::size_t attempts = 0;
  while (pairs.size() < sampling.pairs && attempts < sampling.max_attempts) {
    ++attempts;
    const std::optional<mapping::Vec2> a = draw_free();
    const std::optional<mapping::Vec2> b = draw_free();
    if (!a || !b || (*b - *a).norm() < sampling.min_distance_m) continue;
    const double yaw = 2.0 * 3.14159265358979323846 * unit(rng) - 3.14159265358979323846;
    PlannerPair pair{planning::PlanarPose{*a, yaw}, *b};
    planning::PlanningProblem problem;
    problem.cost = &cost;
    problem.esdf = &esdf;
    problem.start = pair.start;
    problem.goal_W = pair.goal;
    if (reference.plan(problem).found()) pairs.push_back(pair);
  }
  if (pairs.size() < sampling.pairs) {
    throw Error(fmt::format("sample_planner_pairs: only {} of {} connected pairs in {} draws (clearance {:.2f} m, "
                            "distance >= {:.1f} m)",
                            pairs.size(), sampling.pairs, attempts, sampling.clearance_m, sampling.min_distance_m));
  }
  return pairs;
}

std::vector<std::vector<PlannerRun>> run_planners(const mapping::CostMap& cost, const mapping::Esdf2d& esdf,
                                                  const std::vector<const planning::LocalPlanner*>& planners,
                                                  const std::vector<PlannerPair>& pairs) {
  std::vector<std::vector<PlannerRun>> runs(planners.size());
  for (std::size_t k = 0; k < planners.size(); ++k) {
    for (const PlannerPair& pair : pairs) {
      planning::PlanningProblem problem;
      problem.cost = &cost;
      problem.esdf = &esdf;
      problem.start = pair.start;
      problem.goal_W = pair.goal;
      const planning::Plan p = planners[k]->plan(problem);
      runs[k].push_back(PlannerRun{p.found(), p.time_s, p.expanded, p.length_m,
                                   p.found() ? "" : std::string(planning::to_string(p.reason)) + ": " + p.detail});
    }
  }
  return runs;
}

Summary3 summarize(const std::vector<double>& values) {
  if (values.empty()) throw Error("summarize: no values");
  Summary3 s;
  double sum = 0.0;
  s.max = -std::numeric_limits<double>::infinity();
  for (const double v : values) {
    sum += v;
    s.max = std::max(s.max, v);
  }
  s.avg = sum / static_cast<double>(values.size());
  if (values.size() > 1) {
    double ss = 0.0;
    for (const double v : values) ss += (v - s.avg) * (v - s.avg);
    s.std = std::sqrt(ss / static_cast<double>(values.size() - 1));
  }
  return s;
}

}  // namespace navaid::experiments
