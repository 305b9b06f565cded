#include "navaid/experiments/trial_reproduction.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
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
struct TrialMeasure {
  const char* key;
  const char* label;
  double (*ours)(const TrialResult&);
  std::vector<std::pair<double, double>> paper;  ///< mean, SD per condition
  std::vector<bool> paper_significant;           ///< per pair
};

/// A user-study table reproduced with simulated users: the conditions come from the matrix file
/// (key, label, device, overrides), the paper's numbers from here.
struct TrialTableSpec {
  std::string name;        ///< the reproduction's name (navaid reproduce NAME)
  std::string file;        ///< output stem: FILE.md, FILE.csv
  std::string title;       ///< the table's heading
  std::string paper_setup; ///< who the paper's participants were
  std::vector<TrialMeasure> measures;
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

void run_trial_table(const TrialTableSpec& spec, const fs::path& matrix, const ReproductionRequest& request,
                     const ReproductionEnvironment& env) {
  if (!fs::is_regular_file(matrix)) throw IoError(matrix.string(), "no such reproduction matrix");
  const YAML::Node m = YAML::LoadFile(matrix.string());
  fs::create_directories(request.out);
  const auto text = [&m, &matrix](const char* key) {
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
    s.quiet = true;
    if (env.say) env.say(fmt::format("{}: {} trials with {}", c.label, seeds, c.device));
    std::vector<TrialResult> trials;
    summaries[i] = run_trial_study(s, request.out / c.key, &trials);
    for (const TrialResult& r : trials)
      for (const TrialMeasure& p : spec.measures) ours[i][p.key].push_back(p.ours(r));
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
    for (const auto& [mean, sd] : p.paper) {
      md << fmt::format(" {:.2f} ± {:.2f} |", mean, sd);
      csv << fmt::format(",{},{}", mean, sd);
    }
    for (std::size_t i = 0; i < conditions.size(); ++i) {
      const MeanInterval mi = mean_interval(ours[i][p.key]);
      md << fmt::format(" {:.2f} ± {:.2f} |", mi.mean, mi.std);
      csv << fmt::format(",{:.6f},{:.6f}", mi.mean, mi.std);
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const auto& [a, b] = pairs[k];
      const auto& x = ours[a][p.key];
      const auto& y = ours[b][p.key];
      const WelchTest w = welch_t_test(x, y);
      md << fmt::format(" {:.3f} |", w.p);
      csv << fmt::format(",{:.6f},{:.6f}", w.t, w.p);
      if ((w.p < 0.05) != p.paper_significant[k])
        mismatched.push_back(fmt::format("{} ({} vs {}: {})", p.label, conditions[a].label, conditions[b].label,
                                         w.p < 0.05 ? "significant here, not in the paper" : "not significant here"));
      ++orders;
      if ((p.paper[a].first < p.paper[b].first) == (mean_interval(x).mean < mean_interval(y).mean)) ++same_order;
    }
    md << "\n";
    csv << "\n";
  }
  md << "\n" << spec.footnote << "\n\nSuccess (reached the goal area):";
  for (std::size_t i = 0; i < conditions.size(); ++i)
    md << fmt::format(" {} {:.0f} %{}", conditions[i].label, 100 * summaries[i]["success"]["rate"].get<double>(),
                      i + 1 < conditions.size() ? "," : ".\n");

  std::ofstream v(request.out / "verdict.md");
  v << "# Verdict: " << spec.name << " (simulated users, not human results)\n\n" << spec.finding << "\n\n";
  if (mismatched.empty())
    v << fmt::format("**Agrees**: with {} simulated users per condition, every difference the paper calls significant "
                     "is significant here (Welch p < 0.05) and every other one is not.",
                     seeds);
  else
    v << fmt::format("**Differs**: with {} simulated users per condition, {}.", seeds, fmt::join(mismatched, "; "));
  v << fmt::format(" The ordering of the means matches the paper's in {} of {} comparisons.\n", same_order, orders);
  if (env.say) env.say("wrote " + (request.out / (spec.file + ".md")).string());
}

double duration(const TrialResult& r) { return r.duration_s; }
double cane_contacts(const TrialResult& r) { return static_cast<double>(r.cane_contacts); }
double body_contacts(const TrialResult& r) { return static_cast<double>(r.body_contacts); }
double all_contacts(const TrialResult& r) { return static_cast<double>(r.body_contacts + r.cane_contacts); }

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

}  // namespace navaid::experiments
