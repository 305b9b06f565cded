#include "navaid/experiments/trial_reproduction.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction_statistics.hpp"
#include "navaid/experiments/trial_study.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

/// One measure of a user-study table: how we read it off a trial, and the paper's mean and SD per
/// condition (in the matrix's condition order) with, per pair of conditions (0-1, 0-2, 1-2, ...),
/// whether the paper found the difference significant.
/// A paper's value: mean and SD where it prints them; NaN where it does not (a figure we cannot
/// read numbers off, an SD it does not give).
struct PaperValue {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();
};
constexpr PaperValue kNotGiven{};

struct TrialMeasure {
  const char* key;
  const char* label;
  double (*ours)(const TrialResult&);
  std::vector<PaperValue> paper;     ///< per condition
  std::vector<bool> paper_significant;  ///< per pair; empty: the paper tests nothing (see claims)
};

/// What a paper's text says of two conditions' means: condition `a`'s is lower (`a_lower`) or
/// higher than `b`'s.
struct PaperClaim {
  const char* measure;  ///< TrialMeasure::key
  std::size_t a, b;
  bool a_lower;
  const char* quote;    ///< the paper's words
};

/// A user-study table reproduced with simulated users: the conditions come from the matrix file
/// (key, label, device, overrides), the paper's numbers from here.
struct TrialTableSpec {
  std::string name;        ///< the reproduction's name (navaid reproduce NAME)
  std::string file;        ///< output stem: FILE.md, FILE.csv
  std::string title;       ///< the table's heading
  std::string paper_setup; ///< who the paper's participants were
  std::vector<TrialMeasure> measures;
  /// When the paper states orderings in words instead of tests (eLabrador): the verdict counts how
  /// many hold here.
  std::vector<PaperClaim> claims;
  std::string finding;     ///< the paper's finding, for the verdict
  std::string footnote;    ///< how our numbers differ in kind
};

struct Condition {
  std::string key, label, device;
  std::vector<std::string> overrides;
};

std::vector<std::pair<std::size_t, std::size_t>> condition_pairs(std::size_t n) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b) pairs.emplace_back(a, b);
  return pairs;
}

std::vector<Condition> read_conditions(const YAML::Node& m, const fs::path& matrix, std::size_t expected) {
  if (!m["conditions"] || !m["conditions"].IsSequence())
    throw ConfigError(matrix.string(), "conditions", "is required: a list of {key, label, device, set}");
  std::vector<Condition> out;
  for (const YAML::Node& n : m["conditions"]) {
    Condition c;
    if (!n["key"] || !n["label"] || !n["device"])
      throw ConfigError(matrix.string(), "conditions", "each condition needs key, label and device");
    c.key = n["key"].as<std::string>();
    c.label = n["label"].as<std::string>();
    c.device = n["device"].as<std::string>();
    if (n["set"]) c.overrides = n["set"].as<std::vector<std::string>>();
    out.push_back(std::move(c));
  }
  if (out.size() != expected)
    throw ConfigError(matrix.string(), "conditions", fmt::format("the paper's table has {} conditions, not {}", expected, out.size()));
  return out;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// The mean of a measure's values, NaN when no trial defines it (a time of successful trials when
/// none succeeded).
MeanInterval mean_of(const std::vector<double>& values) {
  if (values.empty()) {
    MeanInterval m;
    m.mean = m.std = kNaN;
    return m;
  }
  return mean_interval(values);
}

std::string paper_cell(const PaperValue& v) {
  if (std::isnan(v.mean)) return "–";
  return std::isnan(v.sd) ? fmt::format("{:.2f}", v.mean) : fmt::format("{:.2f} ± {:.2f}", v.mean, v.sd);
}

/// What run_trial_table concluded, for a reproduction of several tables.
struct TableVerdict {
  bool agrees = false;
  std::string text;  ///< the verdict's sentences
};

/// Runs the table's conditions on `scenario` (empty: the matrix's) and writes its files into
/// request.out; `verdict_file` false leaves verdict.md to the caller.
TableVerdict run_trial_table(const TrialTableSpec& spec, const fs::path& matrix, const ReproductionRequest& request,
                             const ReproductionEnvironment& env, const std::string& scenario = {},
                             bool verdict_file = true) {
  if (!fs::is_regular_file(matrix)) throw IoError(matrix.string(), "no such reproduction matrix");
  const YAML::Node m = YAML::LoadFile(matrix.string());
  fs::create_directories(request.out);
  const auto text = [&m, &matrix, &scenario](const char* key) {
    if (std::string(key) == "scenario" && !scenario.empty()) return scenario;
    if (!m[key]) throw ConfigError(matrix.string(), key, "is required");
    return m[key].as<std::string>();
  };
  const std::vector<Condition> conditions = read_conditions(m, matrix, spec.measures.front().paper.size());
  const auto pairs = condition_pairs(conditions.size());
  std::size_t seeds = request.quick && m["quick"] ? m["quick"]["seeds"].as<std::size_t>() : m["seeds"].as<std::size_t>();
  if (request.seeds > 0) seeds = request.seeds;
  if (seeds < 2) throw UsageError(spec.name + " needs at least 2 seeds (a t test)");

  // condition -> measure -> one value per simulated participant
  std::vector<std::map<std::string, std::vector<double>>> ours(conditions.size());
  std::vector<nlohmann::ordered_json> summaries(conditions.size());
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    const Condition& c = conditions[i];
    TrialStudySpec s;
    s.scenario = text("scenario");
    s.device = c.device;
    s.user = text("user");
    s.first_seed = 1;
    s.last_seed = seeds;
    s.jobs = static_cast<unsigned>(std::max(1, request.jobs));
    s.overrides = c.overrides;
    if (m["set"]) {
      const auto common = m["set"].as<std::vector<std::string>>();
      s.overrides.insert(s.overrides.begin(), common.begin(), common.end());
    }
    s.quiet = true;
    if (env.say) env.say(fmt::format("{}{}: {} trials with {}", scenario.empty() ? "" : scenario + ", ", c.label, seeds, c.device));
    std::vector<TrialResult> trials;
    summaries[i] = run_trial_study(s, request.out / c.key, &trials);
    for (const TrialResult& r : trials)
      for (const TrialMeasure& p : spec.measures)
        if (const double v = p.ours(r); !std::isnan(v)) ours[i][p.key].push_back(v);  // NaN: not defined here
  }

  std::ofstream md(request.out / (spec.file + ".md"));
  std::ofstream csv(request.out / (spec.file + ".csv"));
  csv << "measure";
  for (const Condition& c : conditions) csv << ",paper_" << c.key << "_mean,paper_" << c.key << "_sd";
  for (const Condition& c : conditions) csv << ",ours_" << c.key << "_mean,ours_" << c.key << "_sd";
  for (const auto& [a, b] : pairs)
    csv << ",ours_welch_t_" << conditions[a].key << "_" << conditions[b].key << ",ours_welch_p_" << conditions[a].key
        << "_" << conditions[b].key;
  csv << "\n";
  md << "# " << spec.title << " (simulated users, not human results)\n\n"
     << fmt::format("Paper: {}. Ours: {} simulated `{}` users per condition in closed loop (`navaid trial`, seeds "
                    "1..{}, the same people in every condition). Mean ± SD; p: Welch's t test.\n\n",
                    spec.paper_setup, seeds, text("user"), seeds)
     << "| measure |";
  for (const Condition& c : conditions) md << " paper " << c.label << " |";
  for (const Condition& c : conditions) md << " ours " << c.label << " |";
  for (const auto& [a, b] : pairs) md << " p " << conditions[a].label << " vs " << conditions[b].label << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < 2 * conditions.size() + pairs.size(); ++k) md << "---|";
  md << "\n";

  std::vector<std::string> mismatched;  // pairs whose significance differs from the paper's
  std::size_t same_order = 0, orders = 0;
  for (const TrialMeasure& p : spec.measures) {
    md << "| " << p.label << " |";
    csv << p.key;
    for (const PaperValue& v : p.paper) {
      md << " " << paper_cell(v) << " |";
      csv << (std::isnan(v.mean) ? std::string(",,") : fmt::format(",{},{}", v.mean, std::isnan(v.sd) ? std::string() : fmt::format("{}", v.sd)));
    }
    for (std::size_t i = 0; i < conditions.size(); ++i) {
      const MeanInterval mi = mean_of(ours[i][p.key]);
      md << (std::isnan(mi.mean) ? std::string(" – |") : fmt::format(" {:.2f} ± {:.2f} |", mi.mean, mi.std));
      csv << fmt::format(",{:.6f},{:.6f}", mi.mean, mi.std);
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const auto& [a, b] = pairs[k];
      const auto& x = ours[a][p.key];
      const auto& y = ours[b][p.key];
      const WelchTest w = x.size() >= 2 && y.size() >= 2 ? welch_t_test(x, y) : WelchTest{kNaN, kNaN, kNaN};
      md << fmt::format(" {:.3f} |", w.p);
      csv << fmt::format(",{:.6f},{:.6f}", w.t, w.p);
      if (!p.paper_significant.empty() && (w.p < 0.05) != p.paper_significant[k])
        mismatched.push_back(fmt::format("{} ({} vs {}: {})", p.label, conditions[a].label, conditions[b].label,
                                         w.p < 0.05 ? "significant here, not in the paper" : "not significant here"));
      if (std::isnan(p.paper[a].mean) || std::isnan(p.paper[b].mean) || x.empty() || y.empty()) continue;
      ++orders;
      if ((p.paper[a].mean < p.paper[b].mean) == (mean_of(x).mean < mean_of(y).mean)) ++same_order;
    }
    md << "\n";
    csv << "\n";
  }
  // The paper's orderings in words, each checked on our means.
  std::size_t claims_held = 0;
  std::vector<std::string> claims_failed;
  if (!spec.claims.empty()) md << "\nThe paper's statements, on our means:\n\n";
  for (const PaperClaim& c : spec.claims) {
    const double ma = mean_of(ours[c.a][c.measure]).mean, mb = mean_of(ours[c.b][c.measure]).mean;
    const bool held = c.a_lower ? ma < mb : ma > mb;
    claims_held += held ? 1 : 0;
    const std::string what = fmt::format("{} {} {} {} ({:.2f} vs {:.2f})", c.measure, conditions[c.a].label,
                                         c.a_lower ? "<" : ">", conditions[c.b].label, ma, mb);
    if (!held) claims_failed.push_back(what);
    md << fmt::format("- {} \"{}\": {}\n", held ? "holds" : "**does not hold**", c.quote, what);
  }
  md << "\n" << spec.footnote << "\n\nSuccess (" << (spec.claims.empty() ? "reached the goal area" : "as the trial defines it") << "):";
  for (std::size_t i = 0; i < conditions.size(); ++i)
    md << fmt::format(" {} {:.0f} %{}", conditions[i].label, 100 * summaries[i]["success"]["rate"].get<double>(),
                      i + 1 < conditions.size() ? "," : ".\n");

  TableVerdict verdict;
  if (!spec.claims.empty()) {
    verdict.agrees = claims_failed.empty();
    verdict.text = fmt::format("**{}**: with {} simulated users per condition, {} of {} of the paper's statements hold{}{}.",
                               verdict.agrees ? "Agrees" : "Differs", seeds, claims_held, spec.claims.size(),
                               claims_failed.empty() ? "" : "; not: ", fmt::join(claims_failed, "; "));
  } else if (mismatched.empty()) {
    verdict.agrees = true;
    verdict.text = fmt::format("**Agrees**: with {} simulated users per condition, every difference the paper calls "
                               "significant is significant here (Welch p < 0.05) and every other one is not.",
                               seeds);
  } else {
    verdict.text = fmt::format("**Differs**: with {} simulated users per condition, {}.", seeds, fmt::join(mismatched, "; "));
  }
  if (orders > 0)
    verdict.text += fmt::format(" The ordering of the means matches the paper's in {} of {} comparisons.", same_order, orders);
  if (verdict_file) {
    std::ofstream v(request.out / "verdict.md");
    v << "# Verdict: " << spec.name << " (simulated users, not human results)\n\n" << spec.finding << "\n\n"
      << verdict.text << "\n";
  }
  if (env.say) env.say("wrote " + (request.out / (spec.file + ".md")).string());
  return verdict;
}

double duration(const TrialResult& r) { return r.duration_s; }
double cane_contacts(const TrialResult& r) { return static_cast<double>(r.cane_contacts); }
double body_contacts(const TrialResult& r) { return static_cast<double>(r.body_contacts); }
double success(const TrialResult& r) { return r.success ? 1.0 : 0.0; }
double experimenter_corrections(const TrialResult& r) { return static_cast<double>(r.experimenter_corrections); }
double walking_speed(const TrialResult& r) { return r.mean_speed_mps; }
double all_contacts(const TrialResult& r) { return static_cast<double>(r.body_contacts + r.cane_contacts); }
double time_if_successful(const TrialResult& r) { return r.success ? r.duration_s : kNaN; }

}  // namespace

void run_augmented_cane_table3_3(const fs::path& matrix, const ReproductionRequest& request,
                                 const ReproductionEnvironment& env) {
  // Tables 3.1 and 3.2 (11 volunteers each): completion time, cane contacts, body contacts. The
  // thesis's Table 3.3 finds no significant difference in any of them (t test).
  TrialTableSpec spec;
  spec.name = "augmented-cane-table3.3";
  spec.file = "table3.3";
  spec.title = "BYU augmented cane, Table 3.3: FICF vs CACF on the obstacle course";
  spec.paper_setup = "11 blindfolded volunteers per cost function (Tables 3.1, 3.2)";
  spec.measures = {{"duration_s", "completion time [s]", duration, {{133.67, 33.67}, {123.82, 23.21}}, {false}},
                   {"cane_contacts", "cane contacts", cane_contacts, {{0.64, 1.29}, {1.73, 1.01}}, {false}},
                   {"body_contacts", "body contacts", body_contacts, {{0.73, 0.79}, {0.36, 0.52}}, {false}}};
  spec.finding =
      "The thesis finds no statistically significant difference between FICF and CACF in completion time, cane "
      "contacts or body contacts (t tests, 11 volunteers each).";
  spec.footnote =
      "Ours count every touch of the cane or the body, walls and dividers included (the thesis counts obstacle "
      "contacts); the simulated course is walked without the volunteers' hesitations, so compare the difference "
      "between the cost functions, not the absolute numbers.";
  run_trial_table(spec, matrix, request, env);
}

void run_smart_cane_table2(const fs::path& matrix, const ReproductionRequest& request,
                           const ReproductionEnvironment& env) {
  // Table II (10 limited-vision participants, each method once): duration and contact times; an
  // ANOVA with Tukey's HSD finds every pair different (2P-A* p < 0.05, 2P-WPG p < 5e-4, A*-WPG
  // p < 5e-3) in both measures.
  TrialTableSpec spec;
  spec.name = "smart-cane-table2";
  spec.file = "table2";
  spec.title = "Smart Cane Table II: two-point touch vs A* vs WPG guidance in the corridor";
  spec.paper_setup =
      "10 limited-vision participants, each with the white cane's two-point touch, A* guidance and WPG guidance "
      "(Table II; ANOVA and Tukey's HSD)";
  spec.measures = {
      {"duration_s", "duration [s]", duration, {{23.56, 7.36}, {16.42, 1.98}, {10.28, 1.48}}, {true, true, true}},
      {"contacts", "contact times", all_contacts, {{6.0, 1.06}, {2.57, 0.9}, {0.77, 0.9}}, {true, true, true}}};
  spec.finding =
      "The paper finds WPG guidance fastest with the fewest contacts, A* second and the two-point touch last, every "
      "pair significantly different in both measures.";
  spec.footnote =
      "Ours count every touch of the body or the white cane, walls included; a trial that does not reach the goal "
      "counts with its time at the timeout, so the durations of unsuccessful conditions are bounded by it. Our "
      "devices sense with the cane's RGB-D camera (Smart Cane V1); the paper's study used V2's LiDAR.";
  run_trial_table(spec, matrix, request, env);
}


void run_w_roma_table2(const fs::path& matrix, const ReproductionRequest& request, const ReproductionEnvironment& env) {
  // Table II (5 volunteers x 5 trials per condition): success (grasped within 2 minutes, not a
  // wrong object) and the time of the task; the text gives the totals only, no SDs or tests.
  TrialTableSpec spec;
  spec.name = "w-roma-table2";
  spec.file = "table2";
  spec.title = "W-ROMA Table II: reaching for an object without and with W-ROMA";
  spec.paper_setup = "5 blindfolded sighted volunteers, 5 trials each without and with W-ROMA (Table II)";
  spec.measures = {{"success", "success (touched or grasped within 2 min)", success, {{0.32}, {0.96}}, {}},
                   {"time_s", "time of a successful search [s]", time_if_successful, {{29.1}, {15.6}}, {}}};
  spec.claims = {
      {"success", 0, 1, true, "the total success rate of trials was improved three times, from 32% to 96%"},
      {"time_s", 1, 0, true, "the average time for task completion was halved, from 29.1s to 15.6 s"}};
  spec.finding =
      "The paper finds that W-ROMA triples the success of blindfolded volunteers reaching for a bowl (32 % to "
      "96 %) and halves the time of the task (29.1 s to 15.6 s).";
  spec.footnote =
      "Ours: each trial the person stands before the object while the device finds it, is led to the navigation "
      "start and turned away from the object, then searches: with W-ROMA by the hand unit's cues, without from "
      "memory (remembered with errors drawn per person) with a spiral sweep of the hand. Success: the hand within "
      "trial.reach.touch_m of the object's box, or a grasp on \"target reached\" within trial.reach.grasp_m, before "
      "trial.reach.time_limit_s. Time: of the successful searches only (–: none succeeded), from the start of the "
      "search.";
  run_trial_table(spec, matrix, request, env);
}

void run_elabrador_fig7_8(const fs::path& matrix, const ReproductionRequest& request,
                          const ReproductionEnvironment& env) {
  // Figs. 7 and 8 (ten participants, each route with W, S and S+W in that order): contacts with
  // obstacles, success (arrived and facing the landmark), the experimenter's corrections, walking
  // speed. The text gives Route 1's contacts (1.0 / 0.7 / 0.5), W's success (0 for all) and
  // corrections (W 0.37, S 0); everything else only as bars and in words.
  const auto spec_for = [](const std::string& route) {
    TrialTableSpec spec;
    spec.name = "elabrador-fig7-8";
    spec.file = "fig" + std::string(route == "route1" ? "7" : "8");
    spec.title = "eLabrador Fig. " + std::string(route == "route1" ? "7 (Route 1)" : "8 (Route 2)") +
                 ": white cane (W) vs eLabrador (S) vs both (S+W)";
    spec.paper_setup = "10 participants (7 visually impaired, 3 blindfolded), each condition once per route, W then S "
                       "then S+W (§V-C/D)";
    const bool r1 = route == "route1";
    spec.measures = {
        {"contacts", "contacts with obstacles", body_contacts,
         {r1 ? PaperValue{1.0} : kNotGiven, r1 ? PaperValue{0.7} : kNotGiven, r1 ? PaperValue{0.5} : kNotGiven}, {}},
        {"success", "success (arrived, facing the landmark)", success, {r1 ? PaperValue{0.0} : kNotGiven, kNotGiven, kNotGiven}, {}},
        {"corrections", "corrections (experimenter)", experimenter_corrections,
         {r1 ? PaperValue{0.37} : kNotGiven, r1 ? PaperValue{0.0} : kNotGiven, kNotGiven}, {}},
        {"speed_mps", "walking speed [m/s]", walking_speed, {kNotGiven, kNotGiven, kNotGiven}, {}}};
    if (r1) {
      spec.claims = {
          {"contacts", 1, 0, true, "guided by our eLabrador, the average number of collisions decreased to 0.7"},
          {"contacts", 2, 1, true, "using both ... collisions were further reduced to an average of 0.5"},
          {"success", 0, 1, true, "the participants with the white cane achieve no success ... participants using our system perform significantly better"},
          {"success", 0, 2, true, "(the same, with both)"},
          {"corrections", 1, 0, true, "with our eLabrador pass Route 1 without any correction, while ... white cane need 0.37"},
          {"speed_mps", 1, 0, true, "additional cognitive load, resulting in a reduction in walking speed"}};
    } else {
      spec.claims = {
          {"contacts", 1, 0, true, "our eLabrador significantly reduces the frequency of contact with obstacles (visually impaired participants)"},
          {"corrections", 1, 0, true, "Compared to the white cane, our eLabrador requires fewer corrections"},
          {"corrections", 2, 1, true, "when the participants use eLabrador and the white cane simultaneously, the correction decreases significantly"},
          {"speed_mps", 1, 0, true, "a reduction in walking speed"}};
    }
    spec.finding =
        "The paper finds that eLabrador reduces contacts with obstacles (further with the white cane), guides "
        "participants to face the destination's landmark where the white cane and a phone's navigation never do, "
        "needs fewer corrections than the white cane, and slows walking (cognitive load).";
    spec.footnote =
        "Contacts: body contacts with any obstacle (the cane's touches are its use, not collisions). Corrections: an "
        "experimenter turns the person back toward the route when they are more than trial.correction.off_route_m "
        "from it or stand trial.correction.stuck_s without having arrived (the paper's experimenter intervened on a "
        "wrong way or a blocked path). Success: stopped within trial.goal_radius_m of the destination, facing its "
        "landmark within trial.face_tolerance_deg. W follows a phone's turn-by-turn directions (turn points off by "
        "trial.turn_point_sigma_m) with the two-point touch; the paper's numbers are from bar charts except those "
        "its text gives (–: not in the text).";
    return spec;
  };
  const YAML::Node m = YAML::LoadFile(matrix.string());
  if (!m["routes"] || !m["routes"].IsSequence())
    throw ConfigError(matrix.string(), "routes", "is required: the scenarios of Fig. 7 and Fig. 8 (route1, route2)");
  std::vector<std::string> lines;
  bool all_agree = true;
  for (const YAML::Node& n : m["routes"]) {
    const std::string route = n.as<std::string>();
    if (route != "route1" && route != "route2")
      throw ConfigError(matrix.string(), "routes", "'" + route + "' is not route1 or route2");
    ReproductionRequest r = request;
    r.out = request.out / route;
    const TableVerdict v = run_trial_table(spec_for(route), matrix, r, env, route, false);
    all_agree = all_agree && v.agrees;
    lines.push_back(fmt::format("- {} ({}): {}", route == "route1" ? "Fig. 7, Route 1" : "Fig. 8, Route 2",
                                (fs::path(route) / (route == "route1" ? "fig7.md" : "fig8.md")).string(), v.text));
  }
  std::ofstream v(request.out / "verdict.md");
  v << "# Verdict: elabrador-fig7-8 (simulated users, not human results)\n\n" << spec_for("route1").finding << "\n\n**"
    << (all_agree ? "Agrees" : "Differs") << "** overall.\n\n" << fmt::format("{}", fmt::join(lines, "\n")) << "\n";
  if (env.say) env.say("wrote " + (request.out / "verdict.md").string());
}

}  // namespace navaid::experiments
