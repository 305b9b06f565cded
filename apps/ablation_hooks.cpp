#include "ablation_hooks.hpp"

#include <memory>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/progress.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::cli {

using experiments::Progress;
using experiments::run_process;
using experiments::self_executable;


namespace {

void append_sets(std::vector<std::string>& argv, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) {
    argv.push_back("--set");
    argv.push_back(a);
  }
}

}  // namespace

experiments::AblationCommands child_process_commands(const experiments::AblationMatrix& matrix,
                                                     const std::filesystem::path& out) {
  const std::string self = self_executable();
  experiments::AblationCommands commands;
  commands.simulate = [self, out](const experiments::AblationRecording& rec, std::uint64_t seed,
                                  const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "simulate", "--scenario", rec.scenario, "--seed", std::to_string(seed),
                                  "--out", folder.string(), "--threads", "1", "--cache", (out / "render-cache").string()};
    append_sets(argv, rec.simulate_overrides);
    return argv;
  };
  commands.run_cell = [self, matrix](const experiments::AblationCell& c, const std::filesystem::path& recording,
                                     const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "run", "--recording", recording.string(), "--out", folder.string(), "--no-plot"};
    append_sets(argv, matrix.run_overrides);
    append_sets(argv, matrix.variants[c.variant].overrides);
    return argv;
  };
  return commands;
}

experiments::AblationHooks child_process_hooks(const experiments::AblationMatrix& matrix,
                                               const std::filesystem::path& out, const std::string& progress_label) {
  const experiments::AblationCommands commands = child_process_commands(matrix, out);
  experiments::AblationHooks hooks;
  hooks.simulate = [commands](const experiments::AblationRecording& rec, std::uint64_t seed,
                              const std::filesystem::path& folder) {
    const std::string log = folder.string() + ".log";
    if (run_process(commands.simulate(rec, seed, folder), log) != 0) throw Error("navaid simulate failed (see " + log + ")");
  };
  hooks.run_cell = [commands, out, matrix](const experiments::AblationCell& c, const std::filesystem::path& recording,
                                           const std::filesystem::path& folder) {
    return run_process(commands.run_cell(c, recording, folder), experiments::cell_log(matrix, c, out).string());
  };
  // Shared by the copies of the hooks; created at the first cell, when the total is known.
  auto progress = std::make_shared<std::unique_ptr<Progress>>();
  hooks.on_cell = [progress, progress_label](std::size_t done, std::size_t total) {
    if (!*progress) *progress = std::make_unique<Progress>(progress_label, total);
    (*progress)->update(done);
  };
  return hooks;
}

void EngineOptions::add_to(CLI::App& cmd) {
  cmd.add_option("--engine", engine, "Run the cells with the local pool or as Snakemake jobs (docs/cluster.md)")
      ->check(CLI::IsMember({"local", "snakemake"}))
      ->capture_default_str();
  cmd.add_option("--profile", profile, "Snakemake profile, e.g. experiments/workflow/slurm (with --engine snakemake)")
      ->check(CLI::ExistingDirectory);
  cmd.add_option("--snakemake-arg", snakemake_arguments, "An argument passed to snakemake as it is (repeatable)")
      ->allow_extra_args(false);
}

std::vector<experiments::CellOutcome> run_study(const experiments::AblationMatrix& matrix,
                                                const std::filesystem::path& out, int jobs,
                                                const EngineOptions& engine, const std::string& progress_label) {
  if (engine.engine == "local") {
    if (!engine.profile.empty() || !engine.snakemake_arguments.empty())
      throw UsageError("--profile and --snakemake-arg need --engine snakemake");
    const auto hooks = child_process_hooks(matrix, out, progress_label);  // the progress bar ends with the hooks
    return experiments::run_ablation(matrix, out, jobs, hooks);
  }
  experiments::SnakemakeOptions o;
  o.snakefile = std::filesystem::path(experiments::workflow_dir()) / "Snakefile";
  o.profile = engine.profile;
  o.jobs = jobs;
  o.navaid = self_executable();
  o.extra_arguments = engine.snakemake_arguments;
  return experiments::run_ablation_snakemake(matrix, out, child_process_commands(matrix, out), o);
}

}  // namespace navaid::cli
