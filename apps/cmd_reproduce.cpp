// navaid reproduce: a paper's table or figure from its study matrix (docs/reproductions.md).
#include <fmt/format.h>

#include <cstdlib>
#include <iostream>
#include <memory>

#include "ablation_hooks.hpp"
#include "commands.hpp"
#include "navaid/experiments/figure_script.hpp"
#include "navaid/core/errors.hpp"
#include "navaid/experiments/reproduction.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::cli {

using experiments::run_figure_script;
using experiments::figures_dir;


namespace {


struct ReproduceArgs {
  bool list = false;
  std::string name;
  std::filesystem::path out, matrix;
  int jobs = 1;
  std::size_t seeds = 0;
  bool quick = false;
  bool plot = true;
  EngineOptions engine;
};

// The matrices live beside the plotting scripts: experiments/reproductions in the source tree
// (share/navaid/reproductions when installed); $NAVAID_REPRODUCTIONS_DIR overrides.
std::filesystem::path matrices_dir() {
  if (const char* env = std::getenv("NAVAID_REPRODUCTIONS_DIR")) return env;
  return std::filesystem::path(figures_dir()).parent_path() / "reproductions";
}

void run(const ReproduceArgs& a) {
  if (a.list) {
    std::cout << experiments::reproduction_listing();
    return;
  }
  if (a.name.empty()) throw UsageError("navaid reproduce: name a reproduction (navaid reproduce --list shows them)");
  if (a.out.empty()) throw UsageError("navaid reproduce: --out is required");
  const experiments::Reproduction& r = experiments::find_reproduction(a.name);

  experiments::ReproductionRequest request;
  request.out = a.out;
  request.jobs = a.jobs;
  request.seeds = a.seeds;
  request.quick = a.quick;
  request.plot = a.plot;
  request.matrices_dir = matrices_dir();
  if (!a.matrix.empty()) request.matrix = a.matrix;

  experiments::ReproductionEnvironment env;
  env.hooks = [](const experiments::AblationMatrix& m, const std::filesystem::path& out) {
    return child_process_hooks(m, out, "cells");
  };
  if (a.engine.engine != "local")
    env.run_cells = [engine = a.engine](const experiments::AblationMatrix& m, const std::filesystem::path& out, int jobs) {
      return run_study(m, out, jobs, engine, "cells");
    };
  else if (!a.engine.profile.empty() || !a.engine.snakemake_arguments.empty())
    throw UsageError("--profile and --snakemake-arg need --engine snakemake");
  env.plot = [](const std::string& script, const std::vector<std::string>& args) {
    try {
      run_figure_script(script, args);
    } catch (const Error& e) {
      throw Error(std::string(e.what()) + "; the tables are written");
    }
  };
  env.say = [](const std::string& line) { std::cout << line << std::endl; };
  experiments::run_reproduction(r, request, env);
}

}  // namespace

void add_reproduce_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("reproduce", "Reproduce a paper's table or figure (docs/reproductions.md)");
  auto a = std::make_shared<ReproduceArgs>();
  cmd->add_flag("--list", a->list, "List the reproducible tables and figures");
  cmd->add_option("name", a->name, "Which one (see --list)");
  cmd->add_option("--out", a->out, "Output folder (re-running resumes: finished runs are kept)");
  cmd->add_option("--jobs", a->jobs, "Runs in parallel, or jobs queued at once on a cluster (default 1)")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--seeds", a->seeds, "Number of seeds (default: the matrix's)")->check(CLI::Range(1, 1000));
  cmd->add_flag("--quick", a->quick, "The small version (a subset, shorter walks, 2 seeds)");
  cmd->add_option("--matrix", a->matrix, "Run this matrix file instead of the registered one")->check(CLI::ExistingFile);
  cmd->add_flag("!--no-plot", a->plot, "Skip the figures");
  a->engine.add_to(*cmd);
  cmd->callback([a] { run(*a); });
}

}  // namespace navaid::cli
