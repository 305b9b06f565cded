#include "navaid/experiments/reproduction_table_runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <fstream>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction_trajectories.hpp"
#include "navaid/experiments/reproduction_verdict.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw IoError(file.string(), "cannot write");
}

bool finished(const fs::path& cell) { return fs::exists(cell / "summary.json") && !fs::exists(cell / "failure.txt"); }

// The trajectory figure: every method that finished on (recording, first seed) and the ground
// truth. Returns whether it was drawn.
bool write_figure(const TableReproductionSpec& spec, const AblationMatrix& m, const ReproductionRequest& request,
                  const ReproductionEnvironment& env) {
  const std::string wanted = spec.figure_recording + (request.quick ? spec.quick.suffix : "");
  std::size_t r = 0;
  for (std::size_t i = 0; i < m.recordings.size(); ++i)
    if (m.recordings[i].name == wanted) r = i;
  AblationCell cell{r, 0, m.seeds.front()};
  const fs::path gt = recording_folder(m, cell, request.out) / "groundtruth.tum";
  if (!fs::exists(gt)) {
    env.say("no trajectory figure: " + gt.string() + " does not exist");
    return false;
  }
  std::vector<MethodTrajectory> methods;
  for (cell.variant = 0; cell.variant < m.variants.size(); ++cell.variant) {
    const fs::path folder = cell_folder(m, cell, request.out);
    if (finished(folder) && fs::exists(folder / "trajectory.tum"))
      methods.push_back({m.variants[cell.variant].name, folder / "trajectory.tum"});
  }
  if (methods.empty()) {
    env.say("no trajectory figure: no method finished on " + m.recordings[r].name);
    return false;
  }
  const fs::path csv = request.out / "trajectories.csv";
  const auto rmse = write_aligned_trajectories(gt, methods, csv);
  std::string legend;
  for (std::size_t i = 0; i < methods.size(); ++i) legend += fmt::format("{}{}={:.4f} m", i ? ", " : "", methods[i].method, rmse[i]);
  env.say(fmt::format("trajectory figure: {} seed {} (ATE {})", m.recordings[r].name, cell.seed, legend));
  if (!request.plot) return false;
  const std::string title = fmt::format("{}: {} seed {} (top view, 4-DOF aligned)", spec.figure_title, m.recordings[r].name,
                                        cell.seed);
  env.plot("plot_reproduction_trajectories.py",
           {csv.string(), "--out", (request.out / "trajectories.png").string(), "--title", title});
  return true;
}

}  // namespace

void run_table_reproduction(const TableReproductionSpec& spec, const fs::path& matrix_file,
                            const ReproductionRequest& request, const ReproductionEnvironment& env) {
  const auto start = std::chrono::steady_clock::now();
  AblationMatrix m = read_ablation_matrix(matrix_file);
  if (request.quick) apply_quick_subset(m, spec.quick, matrix_file.string());
  set_seed_count(m, request.seeds);
  if (std::find(m.metrics.begin(), m.metrics.end(), spec.metric) == m.metrics.end())
    throw ConfigError(matrix_file.string(), "metrics", "must include " + spec.metric + " (the table's metric)");
  if (m.variants.size() < 2)
    throw ConfigError(matrix_file.string(), "variants", "a comparison needs the proposed method and at least one baseline");
  if (request.jobs < 1) throw Error(fmt::format("jobs must be >= 1, got {}", request.jobs));

  fs::create_directories(request.out);
  if (const std::size_t removed = remove_stale_results(m, request.out))
    env.say(fmt::format("the matrix changed since the last run: {} stale result folders removed", removed));
  const auto cells = ablation_cells(m);
  const auto kept = std::count_if(cells.begin(), cells.end(),
                                  [&](const AblationCell& c) { return finished(cell_folder(m, c, request.out)); });
  env.say(fmt::format("{}{}: {} recordings x {} variants x {} seeds = {} cells ({} finished before), {} jobs, into {}",
                      spec.name, request.quick ? " (quick)" : "", m.recordings.size(), m.variants.size(), m.seeds.size(),
                      cells.size(), kept, request.jobs, request.out.string()));

  std::vector<CellOutcome> outcomes;
  if (env.run_cells) {
    outcomes = env.run_cells(m, request.out, request.jobs);
  } else {
    const AblationHooks hooks = env.hooks(m, request.out);  // its progress ends with it
    outcomes = run_ablation(m, request.out, request.jobs, hooks);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::size_t failed = 0, resumed = 0;
  for (const auto& o : outcomes) {
    failed += o.status == CellStatus::kFailed;
    resumed += o.status == CellStatus::kResumed;
  }
  write_ablation_csv(m, outcomes, request.out / "results.csv");

  const MethodComparison comparison = compare_methods(m, outcomes, spec.metric);
  const std::string footer = fmt::format(
      "\n{} cells ({} run, {} resumed, {} failed); this run took {:.0f} s with {} jobs. Generated by `navaid reproduce {}{}` "
      "from {}.\n",
      outcomes.size(), outcomes.size() - failed - resumed, resumed, failed, seconds, request.jobs, spec.name,
      request.quick ? " --quick" : "", matrix_file.filename().string());
  const std::string table = comparison_markdown(comparison, spec.paper, spec.title);
  write_file(request.out / (spec.stem + ".md"), table + footer);
  write_file(request.out / (spec.stem + ".csv"), comparison_csv(comparison, spec.paper));
  const std::string verdict = verdict_markdown(judge_comparison(comparison, spec.paper), comparison, spec.paper);
  write_file(request.out / "verdict.md", verdict);
  env.say(table + "\n" + verdict + footer);
  for (const auto& o : outcomes)
    if (o.status == CellStatus::kFailed)
      env.say(fmt::format("  failed: {}/{}/seed{}: {}", m.recordings[o.cell.recording].name,
                          m.variants[o.cell.variant].name, o.cell.seed, o.error));

  const bool figure = write_figure(spec, m, request, env);
  env.say(fmt::format("wrote {}.md, {}.csv, verdict.md, results.csv{} in {}", spec.stem, spec.stem,
                      figure ? ", trajectories.csv, trajectories.png" : "", request.out.string()));
}

}  // namespace navaid::experiments
