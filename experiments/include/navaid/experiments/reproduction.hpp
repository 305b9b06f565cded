#pragma once
// The registry of reproducible paper figures and tables (`navaid reproduce --list`). Each entry
// names what it reproduces and produces, and runs from an ablation matrix under
// experiments/reproductions/ (so anyone can read and change what is run) through the ablation
// runner (ablation.hpp): resumable, with simulations made once and re-used by every variant.
// How recordings are simulated, cells run and figures drawn is the caller's (ReproductionEnvironment):
// `navaid reproduce` uses child processes, tests plug in functions.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "navaid/experiments/ablation.hpp"

namespace navaid::experiments {

struct ReproductionRequest {
  std::filesystem::path out;
  int jobs = 1;
  std::size_t seeds = 0;  ///< 0 = the matrix's seeds, else this many (set_seed_count)
  bool quick = false;     ///< the entry's small version (CI, the main job)
  bool plot = true;
  /// The entry's matrix file is looked up here (experiments/reproductions in the source tree) ...
  std::filesystem::path matrices_dir;
  /// ... unless another matrix file is given.
  std::optional<std::filesystem::path> matrix;
};

struct ReproductionEnvironment {
  /// Hooks that simulate recordings and run cells of `matrix` into `out` (progress included).
  std::function<AblationHooks(const AblationMatrix& matrix, const std::filesystem::path& out)> hooks;
  /// When set, runs the cells instead of run_ablation with `hooks` (navaid reproduce --engine
  /// snakemake); the outcomes must be what run_ablation would give.
  std::function<std::vector<CellOutcome>(const AblationMatrix& matrix, const std::filesystem::path& out, int jobs)>
      run_cells;
  /// Runs a script of experiments/figures with arguments; throws when it fails.
  std::function<void(const std::string& script, const std::vector<std::string>& args)> plot;
  /// One line of progress for the terminal.
  std::function<void(const std::string& line)> say;
};

struct Reproduction {
  std::string name;      ///< what `navaid reproduce NAME` takes
  std::string title;
  std::string paper;     ///< the seed file and section
  std::string produces;  ///< the files written into --out
  std::string runs;      ///< how: the matrix, its size, the quick version
  std::string matrix_file;  ///< under ReproductionRequest::matrices_dir
  /// Runs the reproduction from `matrix` (run_reproduction resolves it).
  std::function<void(const std::filesystem::path& matrix, const ReproductionRequest&, const ReproductionEnvironment&)> run;
};

/// Every registered reproduction, in listing order.
const std::vector<Reproduction>& reproductions();

/// Throws UsageError listing the known names when `name` is not registered.
const Reproduction& find_reproduction(const std::string& name);

/// The text of `navaid reproduce --list`.
std::string reproduction_listing();

/// The matrix file a request runs: its own --matrix, else matrices_dir / the entry's file.
std::filesystem::path reproduction_matrix_file(const Reproduction& r, const ReproductionRequest& request);

/// r.run on reproduction_matrix_file(r, request).
void run_reproduction(const Reproduction& r, const ReproductionRequest& request, const ReproductionEnvironment& env);

}  // namespace navaid::experiments
