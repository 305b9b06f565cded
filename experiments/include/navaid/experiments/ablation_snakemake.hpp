#pragma once
// Ablation studies through Snakemake (docs/cluster.md): one job per simulated recording and one per
// cell, locally or on a cluster (Slurm) with a Snakemake profile; the results are then gathered
// from the study folder exactly as run_ablation reports them (same results.csv).
//
// navaid writes OUT/workflow/plan.json (every job: its id, the command it runs, its marker file)
// and runs `snakemake --snakefile experiments/workflow/Snakefile --directory OUT/workflow`. Each
// rule runs `navaid ablate-job PLAN JOB`, which does what run_ablation does for that recording or
// cell (failure.txt when a cell fails, the study goes on) and then writes the job's marker:
//   recordings/<recording>/seed<k>.simulated   (and seed<k>.failure when the simulation failed)
//   cells/<recording>/<variant>/seed<k>/cell.done
// Markers of finished work are written before Snakemake starts and those of failed cells removed,
// so a study resumes as with the local engine, whichever engine ran it before.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "navaid/experiments/ablation.hpp"

namespace navaid::experiments {

/// The commands a job runs (argv, no shell).
struct AblationCommands {
  std::function<std::vector<std::string>(const AblationRecording&, std::uint64_t seed, const std::filesystem::path& folder)>
      simulate;
  std::function<std::vector<std::string>(const AblationCell&, const std::filesystem::path& recording,
                                         const std::filesystem::path& folder)>
      run_cell;
};

struct SnakemakeOptions {
  std::filesystem::path snakefile;  ///< experiments/workflow/Snakefile
  std::filesystem::path profile;    ///< a Snakemake profile folder (e.g. experiments/workflow/slurm); empty = local
  int jobs = 1;                     ///< local cores, or jobs queued at once on a cluster
  std::string navaid;               ///< this program, which the rules call
  std::string snakemake = "snakemake";
  std::vector<std::string> extra_arguments;  ///< passed to snakemake as they are
};

/// Runs the study and returns its outcomes in ablation_cells() order. Throws Error when snakemake
/// cannot be started or fails for a reason other than a cell (its log: OUT/workflow/snakemake.log).
std::vector<CellOutcome> run_ablation_snakemake(const AblationMatrix& matrix, const std::filesystem::path& out,
                                                const AblationCommands& commands, const SnakemakeOptions& options);

/// One job of a plan written by run_ablation_snakemake (`navaid ablate-job`). Throws Error for an
/// unknown job id or an unreadable plan; a failing simulation or cell is recorded, not thrown.
void run_ablation_job(const std::filesystem::path& plan, const std::string& job_id);

}  // namespace navaid::experiments
