#include "navaid/experiments/figure_script.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::experiments {

void run_figure_script(const std::string& script, const std::vector<std::string>& args) {
  std::vector<std::string> argv{"/usr/bin/python3", figures_dir() + "/" + script};
  argv.insert(argv.end(), args.begin(), args.end());
  spdlog::info("running {}", fmt::join(argv, " "));
  const int rc = run_process(argv);
  if (rc != 0) throw Error(fmt::format("the plotting script failed (exit status {}); command: {}", rc, fmt::join(argv, " ")));
}

}  // namespace navaid::experiments
