#pragma once
// Reproductions of the seeds' user studies with simulated users in closed loop (closed_loop_trial.hpp,
// docs/reproductions.md): the paper's numbers beside ours, the same statistics, a computed verdict,
// and the label "simulated users" on every table.
#include <filesystem>

#include "navaid/experiments/reproduction.hpp"

namespace navaid::experiments {

/// BYU Table 3.3: FICF vs CACF on the obstacle course (time, cane contacts, body contacts), Welch's
/// t test per measure as the thesis's. Writes table3.3.md, table3.3.csv, verdict.md and a trial
/// study folder per cost function.
void run_augmented_cane_table3_3(const std::filesystem::path& matrix, const ReproductionRequest& request,
                                 const ReproductionEnvironment& env);

}  // namespace navaid::experiments
