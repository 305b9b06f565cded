// navaid ablate: an ablation study (recordings x variants x seeds) in parallel, resumable, with a
// results table and a figure (docs/ablations.md).
#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/ablation.hpp"
#include "progress.hpp"
#include "run_process.hpp"

namespace navaid::cli {

namespace {

constexpr const char* kPython = "/usr/bin/python3";

struct AblateArgs {
  std::filesystem::path matrix, out;
  int jobs = 1;
  bool plot = true;
};

void append_sets(std::vector<std::string>& argv, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) {
    argv.push_back("--set");
    argv.push_back(a);
  }
}

void run(const AblateArgs& a) {
  const experiments::AblationMatrix m = experiments::read_ablation_matrix(a.matrix);
  std::filesystem::create_directories(a.out);
  const std::string self = self_executable();

  experiments::AblationHooks hooks;
  hooks.simulate = [&](const experiments::AblationRecording& rec, std::uint64_t seed, const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "simulate", "--scenario", rec.scenario, "--seed", std::to_string(seed),
                                  "--out", folder.string(), "--threads", "1", "--cache", (a.out / "render-cache").string()};
    append_sets(argv, rec.simulate_overrides);
    const std::string log = folder.string() + ".log";
    if (run_process(argv, log) != 0) throw Error("navaid simulate failed (see " + log + ")");
  };
  hooks.run_cell = [&](const experiments::AblationCell& c, const std::filesystem::path& recording,
                       const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "run", "--recording", recording.string(), "--out", folder.string()};
    append_sets(argv, m.run_overrides);
    append_sets(argv, m.variants[c.variant].overrides);
    return run_process(argv, experiments::cell_log(m, c, a.out).string());
  };
  std::unique_ptr<Progress> progress;
  hooks.on_cell = [&](std::size_t done, std::size_t total) {
    if (!progress) progress = std::make_unique<Progress>("ablation cells", total);
    progress->update(done);
  };

  const auto outcomes = experiments::run_ablation(m, a.out, a.jobs, hooks);
  if (progress) progress->finish();
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
  cmd->add_option("--jobs", a->jobs, "Cells run in parallel (default 1)")->check(CLI::Range(1, 64));
  cmd->add_flag("!--no-plot", a->plot, "Skip the figure");
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
