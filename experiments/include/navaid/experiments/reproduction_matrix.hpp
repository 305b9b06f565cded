#pragma once
// How a reproduction adapts its ablation matrix to a request (number of seeds, the quick subset)
// and keeps its output folder consistent with the matrix when resuming: a cell run with other
// overrides than the matrix now gives, or on a recording simulated with other overrides, is stale
// and is deleted so that run_ablation runs it again.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "navaid/experiments/ablation.hpp"

namespace navaid::experiments {

/// The matrix's first `count` seeds; when it lists fewer, continued by the next integers after
/// its largest. count = 0 keeps them as they are.
void set_seed_count(AblationMatrix& m, std::size_t count);

/// A small version of a study (CI, the main job): some recordings, few seeds, shorter walks.
struct QuickSubset {
  std::vector<std::string> recordings;           ///< names kept, in the matrix's order
  std::size_t seeds = 2;
  std::vector<std::string> simulate_overrides;   ///< appended to each kept simulated recording
  std::string suffix = "-quick";                 ///< appended to the kept recordings' names, so
                                                 ///< their folders never mix with the full study's
};

/// Throws ConfigError (file = `source`) when the subset names a recording the matrix lacks.
void apply_quick_subset(AblationMatrix& m, const QuickSubset& quick, const std::string& source);

/// Compares the matrix with the one recorded in `out`/matrix-state.json by the previous run,
/// deletes the stale recordings and cells (returning how many folders), and records the current
/// matrix. A missing state file means a fresh folder: nothing is deleted.
std::size_t remove_stale_results(const AblationMatrix& m, const std::filesystem::path& out);

}  // namespace navaid::experiments
