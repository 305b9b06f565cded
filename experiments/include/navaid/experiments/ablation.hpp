#pragma once
// Ablation studies: a matrix of recordings x variants x seeds (docs/ablations.md), run cell by
// cell in parallel, resumable, surviving failing cells, summarised as results.csv and a Markdown
// table. How a recording is prepared and how a cell runs are hooks: `navaid ablate` runs
// `navaid simulate` and `navaid run` as child processes (a crashing cell cannot take the study
// down); tests plug in functions.
//
// Layout under the output folder:
//   recordings/<recording>/seed<k>/   simulated recordings (one per recording and seed)
//   cells/<recording>/<variant>/seed<k>/   one run folder per cell (summary.json when it finished,
//                                          failure.txt when it failed), seed<k>.log beside it
//   results.csv, results.md
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace navaid::experiments {

struct AblationRecording {
  std::string name;
  /// A recording on disk (run once per variant: its data does not change with the seed) ...
  std::optional<std::filesystem::path> path;
  /// ... or a simulated one: `navaid simulate --scenario <scenario> --seed <seed> --set <overrides>`.
  std::string scenario;
  std::vector<std::string> simulate_overrides;
  bool simulated() const { return !path.has_value(); }
};

struct AblationVariant {
  std::string name;
  std::vector<std::string> overrides;  ///< `--set` assignments of `navaid run`
};

struct AblationMatrix {
  std::vector<AblationRecording> recordings;
  std::vector<AblationVariant> variants;  ///< the first is the baseline of the relative improvement
  std::vector<std::uint64_t> seeds = {1};
  /// Dotted keys into each cell's summary.json; the first is the table's metric (lower is better).
  std::vector<std::string> metrics = {"ate.rmse_m"};
  std::vector<std::string> run_overrides;  ///< applied to every cell before the variant's
};

/// Reads a matrix file. Throws ConfigError naming the file and the key on a missing or malformed
/// entry, duplicate or unsafe names (letters, digits, '-', '_', '.'), an empty list, or a
/// recording with both or neither of `path` and `simulate`. Relative paths are relative to the file.
AblationMatrix read_ablation_matrix(const std::filesystem::path& file);

struct AblationCell {
  std::size_t recording = 0;
  std::size_t variant = 0;
  std::uint64_t seed = 0;
};

/// Every cell, recordings outermost, then variants, then seeds; recordings on disk get only the
/// first seed.
std::vector<AblationCell> ablation_cells(const AblationMatrix& matrix);

enum class CellStatus { kDone, kResumed, kFailed };

struct CellOutcome {
  AblationCell cell;
  CellStatus status = CellStatus::kFailed;
  std::map<std::string, double> metrics;  ///< the matrix's metrics found in summary.json
  std::string error;                      ///< why it failed
  double seconds = 0;                     ///< wall time of this run (0 when resumed)
};

struct AblationHooks {
  /// Writes the simulated recording of (recording, seed) into `folder`; throws on failure.
  std::function<void(const AblationRecording&, std::uint64_t seed, const std::filesystem::path& folder)> simulate;
  /// Runs one cell on `recording` into `cell_folder`; returns an exit status (0 = success), which
  /// must leave summary.json in the folder.
  std::function<int(const AblationCell&, const std::filesystem::path& recording, const std::filesystem::path& cell_folder)>
      run_cell;
  /// Progress over the cells (done, total), called from one thread at a time.
  std::function<void(std::size_t, std::size_t)> on_cell;
};

std::filesystem::path cell_folder(const AblationMatrix& m, const AblationCell& c, const std::filesystem::path& out);
std::filesystem::path cell_log(const AblationMatrix& m, const AblationCell& c, const std::filesystem::path& out);
std::filesystem::path recording_folder(const AblationMatrix& m, const AblationCell& c, const std::filesystem::path& out);

/// Runs the study with `jobs` parallel workers: first the simulated recordings that are missing,
/// then every cell without a summary.json. A failing recording fails its cells; a failing cell
/// writes failure.txt and the study goes on. Outcomes are in ablation_cells() order.
std::vector<CellOutcome> run_ablation(const AblationMatrix& matrix, const std::filesystem::path& out, int jobs,
                                      const AblationHooks& hooks);

/// The steps of run_ablation, for engines that run them as separate jobs (ablation_snakemake.hpp):
/// simulating one (recording, seed) returns "" or the error; running one cell writes failure.txt
/// on failure (and resumes a cell with summary.json, as run_ablation does).
std::string simulate_ablation_recording(const AblationMatrix& matrix, const AblationCell& cell,
                                        const std::filesystem::path& out, const AblationHooks& hooks);
CellOutcome run_ablation_cell(const AblationMatrix& matrix, const AblationCell& cell, const std::filesystem::path& out,
                              const AblationHooks& hooks, const std::string& recording_error);
/// The same two steps on explicit folders (a job knows its folders, not the matrix): `simulate`
/// must write `folder`; `run` returns the cell's exit status. The outcome's cell is left unset.
std::string simulate_into(const std::filesystem::path& folder, const std::function<void()>& simulate);
CellOutcome run_cell_in_folder(const std::filesystem::path& folder, const std::filesystem::path& log,
                               const std::function<int()>& run, const std::string& recording_error,
                               const std::vector<std::string>& metrics);

/// A cell job records its wall time here (seconds), beside summary.json or failure.txt.
constexpr const char* kCellSecondsFile = "cell_seconds.txt";
/// A cell's outcome from what is on disk: failure.txt -> failed (its first line the error);
/// summary.json -> done with the recorded seconds, or resumed without them; nothing -> failed.
/// The seconds are those kCellSecondsFile records (0 without it).
CellOutcome read_ablation_cell(const AblationMatrix& matrix, const AblationCell& cell, const std::filesystem::path& out);

/// One row per cell: recording, variant, seed, status, seconds, then one column per metric.
void write_ablation_csv(const AblationMatrix& matrix, const std::vector<CellOutcome>& outcomes,
                        const std::filesystem::path& file);

/// Markdown table of one metric: rows = recordings, columns = variants, cells = mean ± sample std
/// over the finished seeds (n when < all), the best mean per row in bold; then the mean over
/// recordings and each variant's relative change against the first variant.
std::string ablation_markdown(const AblationMatrix& matrix, const std::vector<CellOutcome>& outcomes,
                              const std::string& metric);

}  // namespace navaid::experiments
