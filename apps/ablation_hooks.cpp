#include "ablation_hooks.hpp"

#include <memory>
#include <vector>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/progress.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::cli {

using experiments::Progress;
using experiments::run_process;
using experiments::self_executable;


namespace {

void append_sets(std::vector<std::string>& argv, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) {
    argv.push_back("--set");
    argv.push_back(a);
  }
}

}  // namespace

experiments::AblationHooks child_process_hooks(const experiments::AblationMatrix& matrix,
                                               const std::filesystem::path& out, const std::string& progress_label) {
  const std::string self = self_executable();
  experiments::AblationHooks hooks;
  hooks.simulate = [self, out](const experiments::AblationRecording& rec, std::uint64_t seed,
                               const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "simulate", "--scenario", rec.scenario, "--seed", std::to_string(seed),
                                  "--out", folder.string(), "--threads", "1", "--cache", (out / "render-cache").string()};
    append_sets(argv, rec.simulate_overrides);
    const std::string log = folder.string() + ".log";
    if (run_process(argv, log) != 0) throw Error("navaid simulate failed (see " + log + ")");
  };
  hooks.run_cell = [self, out, matrix](const experiments::AblationCell& c, const std::filesystem::path& recording,
                                       const std::filesystem::path& folder) {
    std::vector<std::string> argv{self, "run", "--recording", recording.string(), "--out", folder.string(), "--no-plot"};
    append_sets(argv, matrix.run_overrides);
    append_sets(argv, matrix.variants[c.variant].overrides);
    return run_process(argv, experiments::cell_log(matrix, c, out).string());
  };
  // Shared by the copies of the hooks; created at the first cell, when the total is known.
  auto progress = std::make_shared<std::unique_ptr<Progress>>();
  hooks.on_cell = [progress, progress_label](std::size_t done, std::size_t total) {
    if (!*progress) *progress = std::make_unique<Progress>(progress_label, total);
    (*progress)->update(done);
  };
  return hooks;
}

}  // namespace navaid::cli
