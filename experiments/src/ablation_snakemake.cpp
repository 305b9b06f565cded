// Ablation studies through Snakemake (ablation_snakemake.hpp).
#include "navaid/experiments/ablation_snakemake.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "navaid/core/errors.hpp"
#include "navaid/experiments/run_process.hpp"

namespace navaid::experiments {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kCellMarker = "cell.done";

fs::path simulated_marker(const fs::path& recording) { return recording.string() + ".simulated"; }
fs::path simulation_failure(const fs::path& recording) { return recording.string() + ".failure"; }

void touch(const fs::path& file, const std::string& text = "") {
  fs::create_directories(file.parent_path());
  std::ofstream out(file);
  out << text;
  if (!out) throw IoError(file.string(), "cannot write");
}

std::string read_first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

std::string simulate_id(const AblationMatrix& m, const AblationCell& c) {
  return "simulate/" + m.recordings[c.recording].name + "/" + std::to_string(c.seed);
}

std::string cell_id(const AblationMatrix& m, const AblationCell& c) {
  return "cell/" + m.recordings[c.recording].name + "/" + m.variants[c.variant].name + "/" + std::to_string(c.seed);
}

// The plan, and the markers set so that Snakemake runs exactly what run_ablation would run.
json write_plan(const AblationMatrix& m, const fs::path& out, const AblationCommands& commands,
                const std::string& navaid) {
  json plan{{"version", 1}, {"out", out.string()}, {"navaid", navaid}, {"jobs", json::array()}};
  std::set<std::string> simulations;
  for (const AblationCell& c : ablation_cells(m)) {
    const AblationRecording& rec = m.recordings[c.recording];
    const fs::path recording = recording_folder(m, c, out);
    std::string needs;
    if (rec.simulated()) {
      const std::string id = simulate_id(m, c);
      needs = simulated_marker(recording).string();
      if (simulations.insert(id).second) {
        const bool complete = fs::exists(recording / "recording.yaml");
        if (complete) touch(simulated_marker(recording));
        else fs::remove(simulated_marker(recording));
        fs::remove(simulation_failure(recording));
        plan["jobs"].push_back({{"id", id},
                                {"kind", "simulate"},
                                {"argv", commands.simulate(rec, c.seed, recording)},
                                {"folder", recording.string()},
                                {"log", recording.string() + ".log"},
                                {"marker", needs}});
      }
    }
    const fs::path folder = cell_folder(m, c, out);
    const bool finished = fs::exists(folder / "summary.json") && !fs::exists(folder / "failure.txt");
    if (finished) touch(folder / kCellMarker);
    else fs::remove(folder / kCellMarker);
    fs::remove(folder / kCellSecondsFile);  // seconds are those of this study run
    plan["jobs"].push_back({{"id", cell_id(m, c)},
                            {"kind", "cell"},
                            {"argv", commands.run_cell(c, recording, folder)},
                            {"folder", folder.string()},
                            {"log", cell_log(m, c, out).string()},
                            {"recording", recording.string()},
                            {"needs", needs},
                            {"marker", (folder / kCellMarker).string()}});
  }
  return plan;
}

std::vector<std::string> strings_of(const json& j) { return j.get<std::vector<std::string>>(); }

// A program name looked up in PATH (run_process starts programs by path, without a shell).
std::string find_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return name;
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
    std::error_code ec;
    if (end > start && fs::is_regular_file(candidate, ec)) return candidate.string();
    start = end + 1;
  }
  throw Error(name + " is not installed (Debian package " + name + "; scripts/install-deps.sh installs it)");
}

}  // namespace

std::vector<CellOutcome> run_ablation_snakemake(const AblationMatrix& m, const fs::path& out_folder,
                                                const AblationCommands& commands, const SnakemakeOptions& o) {
  if (o.jobs < 1) throw UsageError("--jobs must be at least 1");
  if (!fs::exists(o.snakefile)) throw IoError(o.snakefile.string(), "the Snakefile is not there");
  if (!o.profile.empty() && !fs::exists(o.profile / "config.yaml"))
    throw IoError(o.profile.string(), "is not a Snakemake profile (no config.yaml)");
  const fs::path out = fs::absolute(out_folder);
  const fs::path workflow = out / "workflow";
  fs::create_directories(workflow / "logs");
  const fs::path plan_file = workflow / "plan.json";
  {
    std::ofstream plan(plan_file);
    plan << write_plan(m, out, commands, o.navaid).dump(1) << "\n";
    if (!plan) throw IoError(plan_file.string(), "cannot write");
  }
  std::vector<std::string> argv{find_program(o.snakemake), "--snakefile", fs::absolute(o.snakefile).string(), "--directory",
                                workflow.string(), "--config", "plan=" + plan_file.string(), "--keep-going",
                                "--printshellcmds"};
  if (o.profile.empty()) {
    argv.insert(argv.end(), {"--cores", std::to_string(o.jobs)});
  } else {
    argv.insert(argv.end(), {"--profile", fs::absolute(o.profile).string(), "--jobs", std::to_string(o.jobs)});
  }
  argv.insert(argv.end(), o.extra_arguments.begin(), o.extra_arguments.end());
  const fs::path log = workflow / "snakemake.log";
  const int status = run_process(argv, log.string());
  if (status != 0)
    throw Error("snakemake exited with status " + std::to_string(status) + " (see " + log.string() +
                "); cells that finished are kept, re-running resumes");

  std::vector<CellOutcome> outcomes;
  for (const AblationCell& c : ablation_cells(m)) outcomes.push_back(read_ablation_cell(m, c, out));
  return outcomes;
}

void run_ablation_job(const fs::path& plan_file, const std::string& job_id) {
  std::ifstream in(plan_file);
  if (!in) throw IoError(plan_file.string(), "cannot read the plan");
  json plan;
  try {
    plan = json::parse(in);
  } catch (const json::exception& e) {
    throw IoError(plan_file.string(), std::string("is not a plan: ") + e.what());
  }
  for (const json& job : plan.at("jobs")) {
    if (job.at("id") != job_id) continue;
    const fs::path folder = job.at("folder").get<std::string>();
    const std::string log = job.at("log").get<std::string>();
    const std::vector<std::string> argv = strings_of(job.at("argv"));
    if (job.at("kind") == "simulate") {
      fs::remove(simulation_failure(folder));
      const std::string error = simulate_into(folder, [&] {
        if (run_process(argv, log) != 0) throw Error("navaid simulate failed (see " + log + ")");
      });
      if (!error.empty()) touch(simulation_failure(folder), error + "\n");
    } else {
      const std::string needs = job.at("needs").get<std::string>();
      const fs::path failure = needs.empty() ? fs::path() : simulation_failure(job.at("recording").get<std::string>());
      const std::string recording_error = !failure.empty() && fs::exists(failure) ? read_first_line(failure) : "";
      const CellOutcome o = run_cell_in_folder(
          folder, log, [&] { return run_process(argv, log); }, recording_error, {});
      if (o.status != CellStatus::kResumed) touch(folder / kCellSecondsFile, std::to_string(o.seconds) + "\n");
    }
    touch(job.at("marker").get<std::string>());
    return;
  }
  throw Error(plan_file.string() + ": no job '" + job_id + "'");
}

}  // namespace navaid::experiments
