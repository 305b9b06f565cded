#pragma once
// A paper table reproduced by a study: the matrix's variants are the paper's methods (the first is
// the proposed one), its recordings the paper's sequences. Runs the study (resumable: finished
// cells are kept, stale ones re-run, reproduction_matrix.hpp), then writes into the output folder
//   <stem>.md, <stem>.csv   the comparison table with the paper's numbers (reproduction_comparison.hpp)
//   verdict.md              ordering and size of the improvement (reproduction_verdict.hpp)
//   trajectories.csv/.png   top view of every method and the ground truth on one recording and seed
//   results.csv             every cell (the ablation runner's table)
// and prints the table, the verdict and the wall time.
#include <filesystem>
#include <string>

#include "navaid/experiments/reproduction.hpp"
#include "navaid/experiments/reproduction_comparison.hpp"
#include "navaid/experiments/reproduction_matrix.hpp"

namespace navaid::experiments {

struct TableReproductionSpec {
  std::string name;         ///< the registry's name (for the generated files' footers)
  std::string title;        ///< the table's heading
  std::string stem = "table";
  std::string metric = "ate.rmse_m";
  PaperNumbers paper;
  QuickSubset quick;
  /// The recording of the trajectory figure (its quick name when quick); the first recording of
  /// the matrix when it has none of that name. The figure uses the first seed.
  std::string figure_recording;
  std::string figure_title;
};

void run_table_reproduction(const TableReproductionSpec& spec, const std::filesystem::path& matrix_file,
                            const ReproductionRequest& request, const ReproductionEnvironment& env);

}  // namespace navaid::experiments
