// navaid ablate: an ablation study (recordings x variants x seeds) in parallel, resumable, with a
// results table and a figure (docs/ablations.md).
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>
#include <vector>

#include "ablation_hooks.hpp"
#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/ablation.hpp"
#include "navaid/experiments/ablation_snakemake.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::cli {

using experiments::run_process;
using experiments::figures_dir;


namespace {

constexpr const char* kPython = "/usr/bin/python3";

struct AblateArgs {
  std::filesystem::path matrix, out;
  int jobs = 1;
  bool plot = true;
  EngineOptions engine;
};

void run(const AblateArgs& a) {
  const experiments::AblationMatrix m = experiments::read_ablation_matrix(a.matrix);
  std::filesystem::create_directories(a.out);
  const std::vector<experiments::CellOutcome> outcomes = run_study(m, a.out, a.jobs, a.engine);
  experiments::write_ablation_csv(m, outcomes, a.out / "results.csv");
  std::string md;
  for (const auto& metric : m.metrics) md += experiments::ablation_markdown(m, outcomes, metric) + "\n";
  std::ofstream(a.out / "results.md") << md;

  std::size_t failed = 0, resumed = 0;
  for (const auto& o : outcomes) {
    failed += o.status == experiments::CellStatus::kFailed;
    resumed += o.status == experiments::CellStatus::kResumed;
  }
  std::cout << experiments::ablation_markdown(m, outcomes, m.metrics.front()) << "\n";
  std::cout << fmt::format("{} cells: {} run, {} resumed, {} failed; wrote {}, {}\n", outcomes.size(),
                           outcomes.size() - failed - resumed, resumed, failed, (a.out / "results.csv").string(),
                           (a.out / "results.md").string());
  for (const auto& o : outcomes)
    if (o.status == experiments::CellStatus::kFailed)
      std::cout << fmt::format("  failed: {}/{}/seed{}: {}\n", m.recordings[o.cell.recording].name,
                               m.variants[o.cell.variant].name, o.cell.seed, o.error);
  if (a.plot) {
    const std::vector<std::string> argv{kPython, figures_dir() + "/plot_ablation.py", (a.out / "results.csv").string(),
                                        m.metrics.front(), (a.out / "ablation.png").string()};
    if (run_process(argv) != 0) throw Error("the plotting script failed; results.csv and results.md are written");
    std::cout << "wrote " << (a.out / "ablation.png").string() << "\n";
  }
}

}  // namespace

void add_ablate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("ablate", "Run an ablation study: recordings x variants x seeds (docs/ablations.md)");
  auto a = std::make_shared<AblateArgs>();
  cmd->add_option("matrix", a->matrix, "Ablation matrix (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", a->out, "Study folder (re-running resumes: finished cells are kept)")->required();
  cmd->add_option("--jobs", a->jobs, "Cells run in parallel, or jobs queued at once on a cluster (default 1)")
      ->check(CLI::Range(1, 10000));
  cmd->add_flag("!--no-plot", a->plot, "Skip the figure");
  a->engine.add_to(*cmd);
  cmd->callback([a] { run(*a); });

  // What the Snakemake workflow's rules run: one recording or cell of a plan (hidden from --help).
  auto* job = app.add_subcommand("ablate-job", "Run one job of a Snakemake study plan");
  job->group("");
  auto plan = std::make_shared<std::filesystem::path>();
  auto id = std::make_shared<std::string>();
  job->add_option("plan", *plan, "plan.json of navaid ablate --engine snakemake")->required()->check(CLI::ExistingFile);
  job->add_option("job", *id, "The job's id")->required();
  job->callback([plan, id] { experiments::run_ablation_job(*plan, *id); });
}

}  // namespace navaid::cli
