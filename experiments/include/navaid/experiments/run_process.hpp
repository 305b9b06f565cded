#pragma once
// Runs a program with arguments (no shell, so paths need no quoting) and waits for it.
#include <string>
#include <vector>

namespace navaid::experiments {

/// Returns the exit status; throws navaid::Error when the program cannot be started. With a
/// log file, the program's stdout and stderr go there (created or truncated).
int run_process(const std::vector<std::string>& argv, const std::string& log_file = {});

/// This program's own executable, for running navaid subcommands as child processes.
std::string self_executable();

/// The folder holding the plotting scripts: $NAVAID_FIGURES_DIR, else the source tree's
/// experiments/figures, else the installed share/navaid/figures.
std::string figures_dir();

/// The folder holding the Snakemake workflow (Snakefile, the Slurm profile):
/// $NAVAID_WORKFLOW_DIR, else experiments/workflow beside the figures folder.
std::string workflow_dir();

}  // namespace navaid::experiments
