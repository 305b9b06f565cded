#pragma once
// Reproductions of the seeds' user studies with simulated users in closed loop (closed_loop_trial.hpp,
// docs/reproductions.md): the paper's numbers beside ours, the same statistics, a computed verdict,
// and the label "simulated users" on every table.
#include <filesystem>

#include "navaid/experiments/reproduction.hpp"

namespace navaid::experiments {

/// The conditions of each table (key, label, device, overrides) come from its matrix file
/// (experiments/reproductions/*.yaml); the paper's numbers are in the code beside the measures.
///
/// BYU Table 3.3: FICF vs CACF on the obstacle course (time, cane contacts, body contacts), Welch's
/// t test per measure as the thesis's. Writes table3.3.md, table3.3.csv, verdict.md and a trial
/// study folder per cost function.
void run_augmented_cane_table3_3(const std::filesystem::path& matrix, const ReproductionRequest& request,
                                 const ReproductionEnvironment& env);

/// Smart Cane Table II: two-point touch (the white cane alone) vs A* vs WPG guidance in the
/// corridor (duration, contacts), Welch's t test per pair against the paper's ANOVA/Tukey findings.
/// Writes table2.md, table2.csv, verdict.md and a trial study folder per condition.
void run_smart_cane_table2(const std::filesystem::path& matrix, const ReproductionRequest& request,
                           const ReproductionEnvironment& env);

/// eLabrador Figs. 7 and 8 (the "Tables III/IV"): route1 and route2 with the white cane
/// and a phone's directions (W), eLabrador (S) and both (S+W), simulated users in closed loop:
/// contacts, success (arrived and facing the landmark), the experimenter's corrections and walking
/// speed beside what the paper's text gives, and a verdict from the orderings it states. Writes
/// route1/fig7.md, route2/fig8.md (and .csv, and a trial study folder per condition) and verdict.md.
void run_elabrador_fig7_8(const std::filesystem::path& matrix, const ReproductionRequest& request,
                          const ReproductionEnvironment& env);

/// W-ROMA Table II: reaching for an object without a device (from memory) and with W-ROMA's hand
/// guidance in the lab (trial.task=reach): success and the time of successful searches beside the
/// paper's totals, a verdict from the orderings its text states. Writes table2.md, table2.csv,
/// verdict.md and a trial study folder per condition.
void run_w_roma_table2(const std::filesystem::path& matrix, const ReproductionRequest& request,
                       const ReproductionEnvironment& env);

}  // namespace navaid::experiments
