#pragma once
// navaid run's top-view figure (topview.png): the estimated track coloured by estimator mode,
// over the ground truth when the recording has one, drawn by experiments/figures/plot_run_topview.py
// from CSV files in <run>/topview.data/.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "navaid/core/messages.hpp"
#include "navaid/evaluation/run_estimate.hpp"
#include "navaid/evaluation/trajectory_alignment.hpp"

namespace navaid::experiments {

/// Plot frame: with `W_to_groundtruth` (the 4-DOF alignment of the ATE), every estimate mapped
/// into the ground truth's frame and the ground truth drawn too (plus the ENU track T_ENU_W T_W_B,
/// unaligned, when GPS registered W: the simulator's ground truth is ENU); without it, ENU when
/// GPS registered W, else W. Initializing frames are left out. Throws navaid::Error when the
/// script fails (the caller decides whether that fails the run) or there is nothing to draw.
void draw_run_topview(const std::filesystem::path& run_dir, const std::vector<evaluation::RunEstimate>& estimates,
                      const std::vector<GroundTruthState>& groundtruth,
                      const std::optional<evaluation::Similarity>& W_to_groundtruth, const std::string& title);

}  // namespace navaid::experiments
