#pragma once
// The ablation runner's hooks as `navaid ablate` and `navaid reproduce` use them: each recording is
// made by `navaid simulate` and each cell run by `navaid run`, as child processes of this program
// (a crashing cell cannot take the study down), with a progress bar over the cells.
#include <filesystem>
#include <string>

#include "navaid/experiments/ablation.hpp"

namespace navaid::cli {

/// Recordings go to OUT/recordings (log beside each, render cache OUT/render-cache), cells to
/// OUT/cells with their logs (docs/ablations.md). The progress bar ends when the last copy of the
/// hooks is destroyed.
experiments::AblationHooks child_process_hooks(const experiments::AblationMatrix& matrix,
                                               const std::filesystem::path& out,
                                               const std::string& progress_label = "ablation cells");

}  // namespace navaid::cli
