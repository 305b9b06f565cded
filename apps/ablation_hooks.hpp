#pragma once
// The ablation runner's hooks as `navaid ablate` and `navaid reproduce` use them: each recording is
// made by `navaid simulate` and each cell run by `navaid run`, as child processes of this program
// (a crashing cell cannot take the study down), with a progress bar over the cells.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "navaid/experiments/ablation.hpp"
#include "navaid/experiments/ablation_snakemake.hpp"

namespace navaid::cli {

/// The commands behind the hooks (navaid simulate / navaid run argv), for the Snakemake engine.
experiments::AblationCommands child_process_commands(const experiments::AblationMatrix& matrix,
                                                     const std::filesystem::path& out);

/// Recordings go to OUT/recordings (log beside each, render cache OUT/render-cache), cells to
/// OUT/cells with their logs (docs/ablations.md). The progress bar ends when the last copy of the
/// hooks is destroyed.
experiments::AblationHooks child_process_hooks(const experiments::AblationMatrix& matrix,
                                               const std::filesystem::path& out,
                                               const std::string& progress_label = "ablation cells");

/// Which engine runs a study's cells: the local thread pool, or Snakemake (locally, or on a cluster
/// with a profile; docs/cluster.md).
struct EngineOptions {
  std::string engine = "local";
  std::filesystem::path profile;
  std::vector<std::string> snakemake_arguments;
  void add_to(CLI::App& cmd);
};

/// Runs every cell of the study with the chosen engine; the outcomes are the same either way.
std::vector<experiments::CellOutcome> run_study(const experiments::AblationMatrix& matrix,
                                                const std::filesystem::path& out, int jobs,
                                                const EngineOptions& engine,
                                                const std::string& progress_label = "ablation cells");

}  // namespace navaid::cli
