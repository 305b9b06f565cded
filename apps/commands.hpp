#pragma once
// Each navaid subcommand registers itself on the top-level CLI11 app.
#include <CLI/CLI.hpp>

namespace navaid::cli {

void add_info_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_plot_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_scenario_map_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_ablate_command(CLI::App& app);
void add_reproduce_command(CLI::App& app);
void add_consistency_command(CLI::App& app);
void add_init_study_command(CLI::App& app);
void add_map_command(CLI::App& app);
void add_plan_command(CLI::App& app);
void add_rumble_command(CLI::App& app);
void add_hand_guide_command(CLI::App& app);
void add_route_command(CLI::App& app);
void add_cues_command(CLI::App& app);
void add_listen_command(CLI::App& app);
void add_device_sim_command(CLI::App& app);
void add_trial_command(CLI::App& app);
void add_config_command(CLI::App& app);

}  // namespace navaid::cli
