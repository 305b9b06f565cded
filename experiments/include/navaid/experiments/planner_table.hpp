#pragma once
// A paper's planner comparison reproduced (Smart Cane Table I: A* vs the walking-path generator):
// maps from simulator scenarios, start / goal pairs drawn from a seed (planner_comparison.hpp),
// every planner on every pair, and per map the average / standard deviation / maximum of search
// time, nodes expanded and path length beside the paper's, with the proposed planner's relative
// change against each baseline (bootstrap interval over the pairs) and a computed verdict. What
// is run is a YAML file under experiments/reproductions/ (smart-cane-table1.yaml).
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "navaid/experiments/planner_comparison.hpp"
#include "navaid/experiments/reproduction.hpp"

namespace navaid::experiments {

struct PlannerTableMap {
  std::string name;
  std::string scenario;
  double resolution_m = 0.1;
  double min_distance_m = 10.0;  ///< straight start-goal distance of the pairs
  /// Config overrides for one planner on this map only, by planner name (YAML `set: {wpg: [...]}`).
  std::map<std::string, std::vector<std::string>> set;
};

struct PlannerTablePlanner {
  std::string name;     ///< the column (e.g. "wpg"); the first planner is the proposed one
  std::string planner;  ///< make_local_planner's name
  std::vector<std::string> set;  ///< config overrides
};

struct PlannerTableSpec {
  std::vector<PlannerTableMap> maps;
  std::vector<PlannerTablePlanner> planners;
  std::size_t pairs = 30;
  std::uint64_t seed = 1;
  double clearance_m = 0.35;
  std::vector<std::string> quick_maps;
  std::size_t quick_pairs = 5;
};

/// Throws ConfigError naming the file and key for a missing or bad field, fewer than two
/// planners, an unknown planner or scenario name is reported when the table runs.
PlannerTableSpec read_planner_table_spec(const std::filesystem::path& file);

/// What the paper reports for one map, per planner name and metric ("time_s", "nodes",
/// "length_m"): {avg, std, max}.
struct PaperPlannerMap {
  std::map<std::string, std::map<std::string, Summary3>> by_planner;
};
struct PaperPlannerTable {
  std::string source;
  std::map<std::string, PaperPlannerMap> by_map;
  std::string note;
};

struct PlannerTableEntry {
  std::string name, title, stem = "table1";
  PaperPlannerTable paper;
};

/// Runs the table into request.out: <stem>.md, <stem>.csv (map, planner, metric, statistic, ours,
/// paper), verdict.md, runs.csv (every planner on every pair), paths-<map>.png (the first pair's
/// plans, the paper's Fig. 10). --quick: the spec's quick maps and pairs; --seeds N: N pairs.
void run_planner_table(const PlannerTableEntry& entry, const std::filesystem::path& spec_file,
                       const ReproductionRequest& request, const ReproductionEnvironment& env);

}  // namespace navaid::experiments
