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

struct PaperMeasure {
  const char* key;
  const char* label;
  double (*ours)(const TrialResult&);
  double ficf_mean, ficf_sd, cacf_mean, cacf_sd;
};

// Tables 3.1 and 3.2 (11 volunteers each): completion time, cane contacts, body contacts. The
// thesis's Table 3.3 finds no significant difference in any of them (t test).
constexpr PaperMeasure kPaper[] = {
    {"duration_s", "completion time [s]", [](const TrialResult& r) { return r.duration_s; }, 133.67, 33.67, 123.82, 23.21},
    {"cane_contacts", "cane contacts", [](const TrialResult& r) { return double(r.cane_contacts); }, 0.64, 1.29, 1.73, 1.01},
    {"body_contacts", "body contacts", [](const TrialResult& r) { return double(r.body_contacts); }, 0.73, 0.79, 0.36, 0.52},
};

}  // namespace

void run_augmented_cane_table3_3(const fs::path& matrix, const ReproductionRequest& request,
                                 const ReproductionEnvironment& env) {
  if (!fs::is_regular_file(matrix)) throw IoError(matrix.string(), "no such reproduction matrix");
  const YAML::Node m = YAML::LoadFile(matrix.string());
  fs::create_directories(request.out);
  const auto text = [&m, &matrix](const char* key) {
    if (!m[key]) throw ConfigError(matrix.string(), key, "is required");
    return m[key].as<std::string>();
  };
  const std::vector<std::string> functions = m["functions"].as<std::vector<std::string>>();
  if (functions.size() != 2) throw ConfigError(matrix.string(), "functions", "must name two cost functions");
  std::size_t seeds = request.quick && m["quick"] ? m["quick"]["seeds"].as<std::size_t>() : m["seeds"].as<std::size_t>();
  if (request.seeds > 0) seeds = request.seeds;
  if (seeds < 2) throw UsageError("augmented-cane-table3.3 needs at least 2 seeds (a t test)");

  std::map<std::string, std::map<std::string, std::vector<double>>> ours;  // function -> measure -> values
  std::map<std::string, nlohmann::ordered_json> summaries;
  for (const std::string& f : functions) {
    TrialStudySpec s;
    s.scenario = text("scenario");
    s.device = text("device");
    s.user = text("user");
    s.first_seed = 1;
    s.last_seed = seeds;
    s.jobs = static_cast<unsigned>(std::max(1, request.jobs));
    s.overrides = {"device.cost_function=" + f};
    s.quiet = true;
    if (env.say) env.say(fmt::format("{}: {} trials with {}", f, seeds, s.device));
    std::vector<TrialResult> trials;
    summaries[f] = run_trial_study(s, request.out / f, &trials);
    for (const TrialResult& r : trials)
      for (const PaperMeasure& p : kPaper) ours[f][p.key].push_back(p.ours(r));
  }
  const std::string& a = functions[0];
  const std::string& b = functions[1];

  std::ofstream md(request.out / "table3.3.md");
  std::ofstream csv(request.out / "table3.3.csv");
  csv << "measure,paper_" << a << "_mean,paper_" << a << "_sd,paper_" << b << "_mean,paper_" << b << "_sd,ours_" << a
      << "_mean,ours_" << a << "_sd,ours_" << b << "_mean,ours_" << b << "_sd,ours_welch_t,ours_welch_p\n";
  md << "# BYU augmented cane, Table 3.3: FICF vs CACF on the obstacle course (simulated users, not human results)\n\n"
     << fmt::format("Paper: 11 blindfolded volunteers per cost function (Tables 3.1, 3.2). Ours: {} simulated "
                    "`{}` users per cost function in closed loop (`navaid trial`, seeds 1..{}, the same people for "
                    "both). Mean ± SD; p: Welch's t test.\n\n",
                    seeds, text("user"), seeds)
     << "| measure | paper FICF | paper CACF | ours FICF | ours CACF | ours p |\n|---|---|---|---|---|---|\n";
  std::vector<std::string> significant;
  std::size_t same_order = 0;
  for (const PaperMeasure& p : kPaper) {
    const auto& x = ours[a][p.key];
    const auto& y = ours[b][p.key];
    const MeanInterval mx = mean_interval(x), my = mean_interval(y);
    const WelchTest w = welch_t_test(x, y);
    if (w.p < 0.05) significant.push_back(p.label);
    if ((p.ficf_mean < p.cacf_mean) == (mx.mean < my.mean)) ++same_order;
    md << fmt::format("| {} | {:.2f} ± {:.2f} | {:.2f} ± {:.2f} | {:.2f} ± {:.2f} | {:.2f} ± {:.2f} | {:.3f} |\n", p.label,
                      p.ficf_mean, p.ficf_sd, p.cacf_mean, p.cacf_sd, mx.mean, mx.std, my.mean, my.std, w.p);
    csv << fmt::format("{},{},{},{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", p.key, p.ficf_mean, p.ficf_sd,
                       p.cacf_mean, p.cacf_sd, mx.mean, mx.std, my.mean, my.std, w.t, w.p);
  }
  md << "\nOurs count every touch of the cane or the body, walls and dividers included (the thesis counts "
        "obstacle contacts); the simulated course is walked without the volunteers' hesitations, so compare the "
        "difference between the cost functions, not the absolute numbers.\n";
  md << fmt::format("\nSuccess (reached the goal area): FICF {:.0f} %, CACF {:.0f} %.\n",
                    100 * summaries[a]["success"]["rate"].get<double>(), 100 * summaries[b]["success"]["rate"].get<double>());

  std::ofstream v(request.out / "verdict.md");
  v << "# Verdict: augmented-cane-table3.3 (simulated users, not human results)\n\n"
    << "The thesis finds no statistically significant difference between FICF and CACF in completion time, cane "
       "contacts or body contacts (t tests, 11 volunteers each).\n\n";
  if (significant.empty())
    v << fmt::format("**Agrees**: with {} simulated users per cost function, no measure differs significantly "
                     "(Welch p >= 0.05 for all three).",
                     seeds);
  else
    v << fmt::format("**Differs**: with {} simulated users per cost function, {} differ{} significantly (p < 0.05).",
                     seeds, fmt::join(significant, " and "), significant.size() == 1 ? "s" : "");
  v << fmt::format(" The ordering of the means matches the paper's in {} of 3 measures.\n", same_order);
  if (env.say) env.say("wrote " + (request.out / "table3.3.md").string());
}

}  // namespace navaid::experiments
