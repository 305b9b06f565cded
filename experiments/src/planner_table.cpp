#include "navaid/experiments/planner_table.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction_statistics.hpp"
#include "navaid/experiments/reproduction_verdict.hpp"
#include "navaid/experiments/scenario_cost_map.hpp"
#include "navaid/planning/config_schema.hpp"
#include "navaid/planning/plan_png.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kMetrics = {"time_s", "nodes", "length_m"};
const std::vector<std::string> kMetricTitles = {"time [s]", "nodes expanded", "path length [m]"};

template <class T>
T field(const YAML::Node& node, const char* key, const std::string& file, const std::string& where) {
  if (!node[key]) throw ConfigError(file, where + key, "is missing");
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception& e) {
    throw ConfigError(file, where + key, std::string("has the wrong type: ") + e.what());
  }
}

// A key the spec does not know is a typo that would silently change what is run.
void known_keys_only(const YAML::Node& node, const std::set<std::string>& known, const std::string& file,
                     const std::string& where) {
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    if (!known.count(k)) throw ConfigError(file, where + k, "unknown key");
  }
}

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw IoError(file.string(), "cannot write");
}

double metric_of(const PlannerRun& r, std::size_t metric) {
  switch (metric) {
    case 0: return r.time_s;
    case 1: return static_cast<double>(r.expanded);
    default: return r.length_m;
  }
}

// One map's results: runs[planner][pair], and the pairs every planner solved.
struct MapResult {
  PlannerTableMap map;
  std::string description;
  std::vector<PlannerPair> pairs;
  std::vector<std::vector<PlannerRun>> runs;
  std::vector<std::size_t> common;
  // [planner][metric] over the common pairs
  std::vector<std::vector<std::optional<Summary3>>> stats;
  // [baseline planner][metric]: proposed vs baseline, change of the means
  std::vector<std::vector<std::optional<RelativeChange>>> change;
};

std::string fmt_value(double v, std::size_t metric) {
  if (metric == 0) return fmt::format("{:.4f}", v);
  if (metric == 1) return fmt::format("{:.1f}", v);
  return fmt::format("{:.2f}", v);
}

std::string pct(double fraction) { return fmt::format("{:+.1f} %", 100.0 * fraction); }

std::optional<Summary3> paper_stat(const PlannerTableEntry& e, const std::string& map, const std::string& planner,
                                   const std::string& metric) {
  const auto m = e.paper.by_map.find(map);
  if (m == e.paper.by_map.end()) return std::nullopt;
  const auto p = m->second.by_planner.find(planner);
  if (p == m->second.by_planner.end()) return std::nullopt;
  const auto s = p->second.find(metric);
  if (s == p->second.end()) return std::nullopt;
  return s->second;
}

std::optional<double> paper_change(const PlannerTableEntry& e, const std::string& map, const std::string& proposed,
                                   const std::string& baseline, const std::string& metric) {
  const auto a = paper_stat(e, map, proposed, metric);
  const auto b = paper_stat(e, map, baseline, metric);
  if (!a || !b || b->avg <= 0.0) return std::nullopt;
  return a->avg / b->avg - 1.0;
}

MapResult run_map(const PlannerTableSpec& spec, const PlannerTableMap& map, std::size_t pairs,
                  const fs::path& spec_file, const ReproductionEnvironment& env, const fs::path& out, bool plot) {
  MapResult r;
  r.map = map;
  const Config map_config = Config::parse(
      "{}", spec_file.string(), {fmt::format("planning.map.resolution_m={}", map.resolution_m)});
  ScenarioCostMap cost = scenario_cost_map(map.scenario, map_config);
  r.description = cost.description;
  mapping::Esdf2d esdf;
  esdf.update(cost.cost);

  std::vector<std::unique_ptr<planning::LocalPlanner>> planners;
  std::vector<const planning::LocalPlanner*> raw;
  for (const auto& entry : map.set) {
    const std::string& name = entry.first;  // a named reference: lambdas may not capture bindings
    if (std::none_of(spec.planners.begin(), spec.planners.end(), [&](const auto& p) { return p.name == name; }))
      throw ConfigError(spec_file.string(), "maps." + map.name + ".set", "names no planner '" + name + "'");
  }
  for (const PlannerTablePlanner& p : spec.planners) {
    std::vector<std::string> overrides = p.set;
    if (const auto it = map.set.find(p.name); it != map.set.end())
      overrides.insert(overrides.end(), it->second.begin(), it->second.end());
    const Config c = Config::parse("{}", spec_file.string(), overrides);
    planners.push_back(planning::make_local_planner(p.planner, c));
    c.reject_unknown_keys(planning::local_planner_schema(p.planner));
    raw.push_back(planners.back().get());
  }
  PairSampling sampling;
  sampling.pairs = pairs;
  sampling.seed = spec.seed;
  sampling.clearance_m = spec.clearance_m;
  sampling.min_distance_m = map.min_distance_m;
  // Pairs are those the first baseline connects: every pair has a path on the paper's terms.
  r.pairs = sample_planner_pairs(cost.cost, esdf, *raw[1], sampling);
  r.runs = run_planners(cost.cost, esdf, raw, r.pairs);

  for (std::size_t i = 0; i < r.pairs.size(); ++i) {
    bool all = true;
    for (const auto& runs : r.runs) all = all && runs[i].found;
    if (all) r.common.push_back(i);
  }
  r.stats.assign(raw.size(), std::vector<std::optional<Summary3>>(kMetrics.size()));
  r.change.assign(raw.size(), std::vector<std::optional<RelativeChange>>(kMetrics.size()));
  for (std::size_t p = 0; p < raw.size(); ++p)
    for (std::size_t m = 0; m < kMetrics.size(); ++m) {
      std::vector<double> v;
      for (const std::size_t i : r.common) v.push_back(metric_of(r.runs[p][i], m));
      if (!v.empty()) r.stats[p][m] = summarize(v);
    }
  for (std::size_t b = 1; b < raw.size(); ++b)
    for (std::size_t m = 0; m < kMetrics.size(); ++m) {
      std::vector<double> a, base;
      for (const std::size_t i : r.common) {
        a.push_back(metric_of(r.runs[0][i], m));
        base.push_back(std::max(metric_of(r.runs[b][i], m), 1e-12));
      }
      if (a.size() >= 2) r.change[b][m] = relative_change_bootstrap(a, base, 0.95, 10000, spec.seed);
    }

  std::size_t failed = 0;
  for (const auto& runs : r.runs)
    for (const PlannerRun& run : runs) failed += !run.found;
  env.say(fmt::format("{}: {} pairs ({} solved by every planner, {} failed runs), {}", map.name, r.pairs.size(),
                      r.common.size(), failed, r.description));
  if (plot && !r.pairs.empty()) {
    // The paper's Fig. 10: every planner's path for the first pair.
    planning::PlanningProblem problem;
    problem.cost = &cost.cost;
    problem.esdf = &esdf;
    problem.start = r.pairs[0].start;
    problem.goal_W = r.pairs[0].goal;
    std::vector<planning::Plan> plans;
    for (const auto* p : raw) plans.push_back(p->plan(problem));
    std::vector<planning::LabelledPlan> labelled;
    for (std::size_t p = 0; p < raw.size(); ++p) labelled.push_back({spec.planners[p].name, &plans[p]});
    planning::write_plan_png(out / ("paths-" + map.name + ".png"), cost.cost, problem, labelled);
  }
  return r;
}

std::string table_markdown(const PlannerTableEntry& e, const PlannerTableSpec& spec, const std::vector<MapResult>& maps) {
  std::string md = "# " + e.title + "\n\n";
  md += "Ours: A* and the walking-path generator on simulated maps of the paper's four environments, start / goal "
        "pairs drawn from seed " +
        std::to_string(spec.seed) + "; statistics over the pairs every planner solved. Paper: " + e.paper.source +
        ".\n";
  for (const MapResult& r : maps) {
    md += fmt::format("\n## {}\n\n{}; {} pairs, {} solved by every planner.\n\n", r.map.name, r.description,
                      r.pairs.size(), r.common.size());
    md += "| metric | statistic |";
    for (const auto& p : spec.planners) md += " " + p.name + " |";
    for (const auto& p : spec.planners) md += " " + p.name + " (paper) |";
    md += "\n|---|---|";
    for (std::size_t i = 0; i < 2 * spec.planners.size(); ++i) md += "---:|";
    md += "\n";
    for (std::size_t m = 0; m < kMetrics.size(); ++m)
      for (const char* stat : {"Avg", "Std", "Max"}) {
        md += fmt::format("| {} | {} |", kMetricTitles[m], stat);
        const auto pick = [&](const Summary3& s) {
          return std::string(stat) == "Avg" ? s.avg : std::string(stat) == "Std" ? s.std : s.max;
        };
        for (std::size_t p = 0; p < spec.planners.size(); ++p)
          md += " " + (r.stats[p][m] ? fmt_value(pick(*r.stats[p][m]), m) : std::string("–")) + " |";
        for (const auto& p : spec.planners) {
          const auto s = paper_stat(e, r.map.name, p.name, kMetrics[m]);
          md += " " + (s ? fmt_value(pick(*s), m) : std::string("–")) + " |";
        }
        md += "\n";
      }
  }
  md += "\n## " + spec.planners[0].name + " against each baseline (change of the means over the pairs, 95 % bootstrap interval)\n\n";
  md += "| map | baseline | metric | ours | paper |\n|---|---|---|---:|---:|\n";
  for (const MapResult& r : maps)
    for (std::size_t b = 1; b < spec.planners.size(); ++b)
      for (std::size_t m = 0; m < kMetrics.size(); ++m) {
        const auto& c = r.change[b][m];
        const auto paper = paper_change(e, r.map.name, spec.planners[0].name, spec.planners[b].name, kMetrics[m]);
        md += fmt::format("| {} | {} | {} | {} | {} |\n", r.map.name, spec.planners[b].name, kMetricTitles[m],
                          c ? fmt::format("{} ({} to {})", pct(c->estimate), pct(c->low), pct(c->high)) : "–",
                          paper ? pct(*paper) : "–");
      }
  if (!e.paper.note.empty()) md += "\n" + e.paper.note + "\n";
  return md;
}

std::string table_csv(const PlannerTableEntry& e, const PlannerTableSpec& spec, const std::vector<MapResult>& maps) {
  std::string csv = "map,planner,metric,statistic,ours,paper\n";
  for (const MapResult& r : maps)
    for (std::size_t p = 0; p < spec.planners.size(); ++p)
      for (std::size_t m = 0; m < kMetrics.size(); ++m) {
        const auto paper = paper_stat(e, r.map.name, spec.planners[p].name, kMetrics[m]);
        const auto& s = r.stats[p][m];
        const auto row = [&](const char* stat, std::optional<double> ours, std::optional<double> theirs) {
          csv += fmt::format("{},{},{},{},{},{}\n", r.map.name, spec.planners[p].name, kMetrics[m], stat,
                             ours ? fmt::format("{:.9g}", *ours) : "", theirs ? fmt::format("{:.9g}", *theirs) : "");
        };
        row("avg", s ? std::optional(s->avg) : std::nullopt, paper ? std::optional(paper->avg) : std::nullopt);
        row("std", s ? std::optional(s->std) : std::nullopt, paper ? std::optional(paper->std) : std::nullopt);
        row("max", s ? std::optional(s->max) : std::nullopt, paper ? std::optional(paper->max) : std::nullopt);
        if (p > 0 && r.change[p][m]) {
          const RelativeChange& c = *r.change[p][m];
          const auto pc = paper_change(e, r.map.name, spec.planners[0].name, spec.planners[p].name, kMetrics[m]);
          csv += fmt::format("{},{},{},change_vs:{},{:.6g},{}\n", r.map.name, spec.planners[0].name, kMetrics[m],
                             spec.planners[p].name, c.estimate, pc ? fmt::format("{:.6g}", *pc) : "");
        }
      }
  return csv;
}

std::string runs_csv(const PlannerTableSpec& spec, const std::vector<MapResult>& maps) {
  std::string csv = "map,pair,start_x,start_y,start_yaw_deg,goal_x,goal_y,planner,found,time_s,nodes,length_m,reason\n";
  for (const MapResult& r : maps)
    for (std::size_t p = 0; p < spec.planners.size(); ++p)
      for (std::size_t i = 0; i < r.pairs.size(); ++i) {
        const PlannerPair& q = r.pairs[i];
        const PlannerRun& run = r.runs[p][i];
        csv += fmt::format("{},{},{:.3f},{:.3f},{:.1f},{:.3f},{:.3f},{},{},{:.6f},{},{:.3f},\"{}\"\n", r.map.name, i,
                           q.start.position.x(), q.start.position.y(), q.start.yaw_rad * 180.0 / 3.14159265358979323846,
                           q.goal.x(), q.goal.y(), spec.planners[p].name, run.found ? 1 : 0, run.time_s, run.expanded,
                           run.length_m, run.reason);
      }
  return csv;
}

std::string verdict_text(const PlannerTableEntry& e, const PlannerTableSpec& spec, const std::vector<MapResult>& maps) {
  const std::string& proposed = spec.planners[0].name;
  std::string md = "# Verdict\n\n";
  for (std::size_t b = 1; b < spec.planners.size(); ++b) {
    const std::string& baseline = spec.planners[b].name;
    for (std::size_t m = 0; m < kMetrics.size(); ++m) {
      std::size_t better = 0, worse = 0;
      std::string lines;
      for (const MapResult& r : maps) {
        const auto paper = paper_change(e, r.map.name, proposed, baseline, kMetrics[m]);
        const ChangeFinding f = classify_change(r.change[b][m], paper);
        const bool is_better = f == ChangeFinding::kSmallerThanPaper || f == ChangeFinding::kLikePaper ||
                               f == ChangeFinding::kLargerThanPaper || f == ChangeFinding::kBetterNoPaper;
        better += is_better;
        worse += f == ChangeFinding::kReversed;
        const auto& c = r.change[b][m];
        const char* word = is_better ? "lower" : f == ChangeFinding::kReversed ? "**higher**" : f == ChangeFinding::kNoData
                                                                                              ? "no data"
                                                                                              : "no significant difference";
        lines += fmt::format("  - {}: {}{}; the paper: {}\n", r.map.name, word,
                             c ? fmt::format(" ({}, 95 % CI {} to {})", pct(c->estimate), pct(c->low), pct(c->high)) : "",
                             paper ? pct(*paper) : "no number");
      }
      md += fmt::format("- **{}** of {} vs {}: lower with confidence on {} of {} maps, higher on {}.\n{}", kMetricTitles[m],
                        proposed, baseline, better, maps.size(), worse, lines);
    }
  }
  return md;
}

}  // namespace

PlannerTableSpec read_planner_table_spec(const fs::path& file) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw IoError(file.string(), std::string("cannot read: ") + e.what());
  }
  const std::string f = file.string();
  if (!root.IsMap()) throw ConfigError(f, "", "expected a map with maps, planners, pairs, seed, clearance_m, quick");
  known_keys_only(root, {"maps", "planners", "pairs", "seed", "clearance_m", "quick"}, f, "");
  PlannerTableSpec s;
  if (!root["maps"] || !root["maps"].IsSequence() || root["maps"].size() == 0)
    throw ConfigError(f, "maps", "needs a list of maps");
  for (std::size_t i = 0; i < root["maps"].size(); ++i) {
    const YAML::Node m = root["maps"][i];
    const std::string where = fmt::format("maps[{}].", i);
    known_keys_only(m, {"name", "scenario", "resolution_m", "min_distance_m", "set"}, f, where);
    PlannerTableMap map;
    map.name = field<std::string>(m, "name", f, where);
    map.scenario = m["scenario"] ? field<std::string>(m, "scenario", f, where) : map.name;
    if (m["resolution_m"]) map.resolution_m = field<double>(m, "resolution_m", f, where);
    if (m["min_distance_m"]) map.min_distance_m = field<double>(m, "min_distance_m", f, where);
    if (!(map.resolution_m > 0.0)) throw ConfigError(f, where + "resolution_m", "must be > 0");
    if (m["set"]) map.set = field<std::map<std::string, std::vector<std::string>>>(m, "set", f, where);
    s.maps.push_back(map);
  }
  if (!root["planners"] || !root["planners"].IsSequence() || root["planners"].size() < 2)
    throw ConfigError(f, "planners", "needs the proposed planner and at least one baseline");
  for (std::size_t i = 0; i < root["planners"].size(); ++i) {
    const YAML::Node p = root["planners"][i];
    const std::string where = fmt::format("planners[{}].", i);
    known_keys_only(p, {"name", "planner", "set"}, f, where);
    PlannerTablePlanner planner;
    planner.name = field<std::string>(p, "name", f, where);
    planner.planner = p["planner"] ? field<std::string>(p, "planner", f, where) : planner.name;
    if (p["set"]) planner.set = field<std::vector<std::string>>(p, "set", f, where);
    s.planners.push_back(planner);
  }
  if (root["pairs"]) s.pairs = field<std::size_t>(root, "pairs", f, "");
  if (root["seed"]) s.seed = field<std::uint64_t>(root, "seed", f, "");
  if (root["clearance_m"]) s.clearance_m = field<double>(root, "clearance_m", f, "");
  if (s.pairs < 2) throw ConfigError(f, "pairs", "needs at least 2 (a spread and an interval)");
  if (root["quick"]) {
    const YAML::Node q = root["quick"];
    known_keys_only(q, {"maps", "pairs"}, f, "quick.");
    if (q["maps"]) s.quick_maps = field<std::vector<std::string>>(q, "maps", f, "quick.");
    if (q["pairs"]) s.quick_pairs = field<std::size_t>(q, "pairs", f, "quick.");
  }
  return s;
}

void run_planner_table(const PlannerTableEntry& entry, const fs::path& spec_file, const ReproductionRequest& request,
                       const ReproductionEnvironment& env) {
  const auto start = std::chrono::steady_clock::now();
  PlannerTableSpec spec = read_planner_table_spec(spec_file);
  std::size_t pairs = spec.pairs;
  if (request.quick) {
    pairs = spec.quick_pairs;
    if (!spec.quick_maps.empty()) {
      std::vector<PlannerTableMap> kept;
      for (const std::string& name : spec.quick_maps) {
        const auto it = std::find_if(spec.maps.begin(), spec.maps.end(), [&](const auto& m) { return m.name == name; });
        if (it == spec.maps.end()) throw ConfigError(spec_file.string(), "quick.maps", "names no map '" + name + "'");
        kept.push_back(*it);
      }
      spec.maps = kept;
    }
  }
  if (request.seeds > 0) pairs = std::max<std::size_t>(2, request.seeds);
  fs::create_directories(request.out);
  env.say(fmt::format("{}{}: {} maps x {} planners x {} pairs, into {}", entry.name, request.quick ? " (quick)" : "",
                      spec.maps.size(), spec.planners.size(), pairs, request.out.string()));
  std::vector<MapResult> maps;
  for (const PlannerTableMap& map : spec.maps) maps.push_back(run_map(spec, map, pairs, spec_file, env, request.out, request.plot));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string footer =
      fmt::format("\nThis run took {:.0f} s. Generated by `navaid reproduce {}{}` from {}. Search times are wall-clock "
                  "times of one thread on this machine (the paper's: an NVIDIA Xavier NX).\n",
                  seconds, entry.name, request.quick ? " --quick" : "", spec_file.filename().string());
  const std::string table = table_markdown(entry, spec, maps);
  write_file(request.out / (entry.stem + ".md"), table + footer);
  write_file(request.out / (entry.stem + ".csv"), table_csv(entry, spec, maps));
  write_file(request.out / "runs.csv", runs_csv(spec, maps));
  const std::string verdict = verdict_text(entry, spec, maps);
  write_file(request.out / "verdict.md", verdict);
  env.say(table + "\n" + verdict + footer);
}

}  // namespace navaid::experiments
