#pragma once
// Runs one of the plotting scripts in experiments/figures/ (figures_dir()) with Debian's python3,
// which has matplotlib (DESIGN.md §5): the one way navaid's commands draw figures.
#include <string>
#include <vector>

namespace navaid::experiments {

/// Runs `python3 <figures_dir()>/<script> <args...>`. Throws navaid::Error naming the command when
/// python cannot be started or the script exits with a non-zero status.
void run_figure_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace navaid::experiments
