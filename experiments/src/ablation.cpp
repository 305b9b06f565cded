#include "navaid/experiments/ablation.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "navaid/core/errors.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

// ---- matrix file -------------------------------------------------------------------------------

struct Reader {
  std::string file;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const { throw ConfigError(file, key, message); }

  std::string name(const YAML::Node& n, const std::string& key) const {
    if (!n || !n.IsScalar()) fail(key, "missing (a name is required)");
    const std::string s = n.as<std::string>();
    const bool safe = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.';
    }) && s != "." && s != "..";
    if (!safe) fail(key, "'" + s + "' is not a usable name (letters, digits, '-', '_', '.')");
    return s;
  }

  std::vector<std::string> strings(const YAML::Node& n, const std::string& key) const {
    std::vector<std::string> out;
    if (!n) return out;
    if (!n.IsSequence()) fail(key, "must be a list of 'key=value' strings");
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsScalar()) fail(fmt::format("{}[{}]", key, i), "must be a string");
      out.push_back(n[i].as<std::string>());
    }
    return out;
  }

  std::vector<std::string> assignments(const YAML::Node& n, const std::string& key) const {
    std::vector<std::string> out = strings(n, key);
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i].find('=') == std::string::npos || out[i].front() == '=')
        fail(fmt::format("{}[{}]", key, i), "'" + out[i] + "' is not a key=value assignment");
    return out;
  }

  void no_unknown_keys(const YAML::Node& n, const std::string& key, std::set<std::string> known) const {
    for (const auto& kv : n) {
      // A list, a map or a tagged empty node as a key (found by fuzz_tables) is no name.
      if (!kv.first.IsScalar()) fail(key.empty() ? "<root>" : key, "a key must be a name, not a list, map or empty node");
      const std::string k = kv.first.as<std::string>();
      if (!known.count(k)) fail(key.empty() ? k : key + "." + k, "unknown key");
    }
  }
};

template <class T>
void require_unique(const std::vector<T>& items, const Reader& r, const char* list) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < items.size(); ++i)
    if (!names.insert(items[i].name).second) r.fail(fmt::format("{}[{}].name", list, i), "duplicate name '" + items[i].name + "'");
}

std::string seed_dir(std::uint64_t seed) { return fmt::format("seed{}", seed); }

// ---- summaries ---------------------------------------------------------------------------------

std::optional<double> lookup(const nlohmann::json& j, const std::string& dotted) {
  const nlohmann::json* node = &j;
  std::stringstream ss(dotted);
  for (std::string part; std::getline(ss, part, '.');) {
    if (!node->is_object() || !node->contains(part)) return std::nullopt;
    node = &(*node)[part];
  }
  if (!node->is_number()) return std::nullopt;
  return node->get<double>();
}

std::map<std::string, double> read_metrics(const fs::path& summary, const std::vector<std::string>& metrics) {
  std::ifstream in(summary);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) throw IoError(summary.string(), "is not valid JSON");
  std::map<std::string, double> out;
  for (const auto& m : metrics)
    if (auto v = lookup(j, m)) out[m] = *v;
  return out;
}

void write_text_file(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw IoError(file.string(), "cannot write");
}

// Runs task(i) for i in [0, n) on `jobs` threads; the first exception is rethrown after all stop.
void parallel_for(std::size_t n, int jobs, const std::function<void(std::size_t)>& task) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        task(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < std::max(1, jobs); ++k) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

struct Stats {
  std::size_t n = 0;
  double mean = 0, std = 0;
};

Stats stats(const std::vector<double>& v) {
  Stats s;
  s.n = v.size();
  if (v.empty()) return s;
  for (double x : v) s.mean += x / static_cast<double>(v.size());
  if (v.size() > 1) {
    double ss = 0;
    for (double x : v) ss += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(ss / static_cast<double>(v.size() - 1));
  }
  return s;
}

}  // namespace

AblationMatrix read_ablation_matrix(const fs::path& file) {
  const Reader r{file.string()};
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    r.fail("<file>", "cannot open the ablation matrix");
  } catch (const YAML::Exception& e) {
    r.fail("<file>", fmt::format("not valid YAML (line {}): {}", e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) r.fail("<root>", "the top level must be a map with recordings, variants and seeds");
  r.no_unknown_keys(root, "", {"recordings", "variants", "seeds", "metrics", "run"});

  AblationMatrix m;
  const YAML::Node recs = root["recordings"];
  if (!recs || !recs.IsSequence() || recs.size() == 0) r.fail("recordings", "must be a non-empty list");
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const std::string key = fmt::format("recordings[{}]", i);
    const YAML::Node n = recs[i];
    if (!n.IsMap()) r.fail(key, "must be a map with name and path or simulate");
    r.no_unknown_keys(n, key, {"name", "path", "simulate"});
    AblationRecording rec;
    rec.name = r.name(n["name"], key + ".name");
    if (n["path"].IsDefined() == n["simulate"].IsDefined()) r.fail(key, "needs exactly one of 'path' and 'simulate'");
    if (n["path"]) {
      if (!n["path"].IsScalar()) r.fail(key + ".path", "must be a path");
      fs::path p = n["path"].as<std::string>();
      rec.path = p.is_absolute() ? p : file.parent_path() / p;
    } else {
      const YAML::Node s = n["simulate"];
      if (!s.IsMap()) r.fail(key + ".simulate", "must be a map with scenario and set");
      r.no_unknown_keys(s, key + ".simulate", {"scenario", "set"});
      if (!s["scenario"] || !s["scenario"].IsScalar()) r.fail(key + ".simulate.scenario", "missing");
      rec.scenario = s["scenario"].as<std::string>();
      rec.simulate_overrides = r.assignments(s["set"], key + ".simulate.set");
    }
    m.recordings.push_back(rec);
  }
  const YAML::Node vars = root["variants"];
  if (!vars || !vars.IsSequence() || vars.size() == 0) r.fail("variants", "must be a non-empty list");
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const std::string key = fmt::format("variants[{}]", i);
    if (!vars[i].IsMap()) r.fail(key, "must be a map with name and set");
    r.no_unknown_keys(vars[i], key, {"name", "set"});
    m.variants.push_back({r.name(vars[i]["name"], key + ".name"), r.assignments(vars[i]["set"], key + ".set")});
  }
  require_unique(m.recordings, r, "recordings");
  require_unique(m.variants, r, "variants");
  if (const YAML::Node seeds = root["seeds"]) {
    if (!seeds.IsSequence() || seeds.size() == 0) r.fail("seeds", "must be a non-empty list of integers >= 0");
    m.seeds.clear();
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      long long v = -1;
      try {
        v = seeds[i].as<long long>();
      } catch (const YAML::Exception&) {
      }
      if (v < 0) r.fail(fmt::format("seeds[{}]", i), "must be an integer >= 0");
      if (std::find(m.seeds.begin(), m.seeds.end(), static_cast<std::uint64_t>(v)) != m.seeds.end())
        r.fail(fmt::format("seeds[{}]", i), "repeated seed");
      m.seeds.push_back(static_cast<std::uint64_t>(v));
    }
  }
  if (root["metrics"]) {
    m.metrics = r.strings(root["metrics"], "metrics");
    if (m.metrics.empty()) r.fail("metrics", "must name at least one summary.json key");
  }
  m.run_overrides = r.assignments(root["run"], "run");
  return m;
}

std::vector<AblationCell> ablation_cells(const AblationMatrix& m) {
  std::vector<AblationCell> cells;
  for (std::size_t r = 0; r < m.recordings.size(); ++r)
    for (std::size_t v = 0; v < m.variants.size(); ++v)
      for (std::size_t s = 0; s < (m.recordings[r].simulated() ? m.seeds.size() : 1); ++s)
        cells.push_back({r, v, m.seeds[s]});
  return cells;
}

fs::path cell_folder(const AblationMatrix& m, const AblationCell& c, const fs::path& out) {
  return out / "cells" / m.recordings[c.recording].name / m.variants[c.variant].name / seed_dir(c.seed);
}

fs::path cell_log(const AblationMatrix& m, const AblationCell& c, const fs::path& out) {
  return cell_folder(m, c, out).string() + ".log";
}

fs::path recording_folder(const AblationMatrix& m, const AblationCell& c, const fs::path& out) {
  const AblationRecording& rec = m.recordings[c.recording];
  return rec.simulated() ? out / "recordings" / rec.name / seed_dir(c.seed) : *rec.path;
}

std::string simulate_into(const fs::path& folder, const std::function<void()>& simulate) {
  try {
    fs::remove_all(folder);  // an interrupted simulation restarts from scratch
    fs::create_directories(folder.parent_path());
    simulate();
    if (!fs::exists(folder / "recording.yaml")) throw Error("the simulation wrote no recording.yaml");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string simulate_ablation_recording(const AblationMatrix& m, const AblationCell& c, const fs::path& out,
                                        const AblationHooks& hooks) {
  const fs::path folder = recording_folder(m, c, out);
  return simulate_into(folder, [&] { hooks.simulate(m.recordings[c.recording], c.seed, folder); });
}

CellOutcome run_cell_in_folder(const fs::path& folder, const fs::path& log, const std::function<int()>& run,
                               const std::string& recording_error, const std::vector<std::string>& metrics) {
  CellOutcome o;
  const auto start = std::chrono::steady_clock::now();
  try {
    if (fs::exists(folder / "summary.json") && !fs::exists(folder / "failure.txt")) {
      o.status = CellStatus::kResumed;
    } else if (!recording_error.empty()) {
      throw Error("recording not available: " + recording_error);
    } else {
      fs::remove_all(folder);
      fs::create_directories(folder);
      const int status = run();
      if (status != 0) throw Error(fmt::format("the run exited with status {} (see {})", status, log.string()));
      if (!fs::exists(folder / "summary.json")) throw Error("the run wrote no summary.json");
      o.status = CellStatus::kDone;
    }
    o.metrics = read_metrics(folder / "summary.json", metrics);
  } catch (const std::exception& e) {
    o.status = CellStatus::kFailed;
    o.error = e.what();
    std::error_code ec;
    fs::create_directories(folder, ec);
    std::ofstream(folder / "failure.txt") << o.error << "\n";
  }
  if (o.status != CellStatus::kResumed)
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return o;
}

CellOutcome run_ablation_cell(const AblationMatrix& m, const AblationCell& c, const fs::path& out,
                              const AblationHooks& hooks, const std::string& recording_error) {
  const fs::path folder = cell_folder(m, c, out);
  CellOutcome o = run_cell_in_folder(
      folder, cell_log(m, c, out), [&] { return hooks.run_cell(c, recording_folder(m, c, out), folder); },
      recording_error, m.metrics);
  o.cell = c;
  return o;
}

CellOutcome read_ablation_cell(const AblationMatrix& m, const AblationCell& c, const fs::path& out) {
  CellOutcome o;
  o.cell = c;
  const fs::path folder = cell_folder(m, c, out);
  try {
    std::ifstream seconds(folder / kCellSecondsFile);
    const bool timed = static_cast<bool>(seconds >> o.seconds);  // run by a job of this study run
    if (fs::exists(folder / "failure.txt")) {
      std::ifstream in(folder / "failure.txt");
      std::getline(in, o.error);
      return o;
    }
    if (!fs::exists(folder / "summary.json")) {
      o.error = "the cell has not run";
      return o;
    }
    o.metrics = read_metrics(folder / "summary.json", m.metrics);
    o.status = timed ? CellStatus::kDone : CellStatus::kResumed;
  } catch (const std::exception& e) {
    o.status = CellStatus::kFailed;
    o.error = e.what();
  }
  return o;
}

std::vector<CellOutcome> run_ablation(const AblationMatrix& m, const fs::path& out, int jobs, const AblationHooks& hooks) {
  const std::vector<AblationCell> cells = ablation_cells(m);

  // Phase 1: simulated recordings that are not complete yet (recording.yaml is written last).
  std::vector<AblationCell> to_simulate;
  for (const auto& c : cells)
    if (c.variant == 0 && m.recordings[c.recording].simulated() &&
        !fs::exists(recording_folder(m, c, out) / "recording.yaml"))
      to_simulate.push_back(c);
  std::map<std::pair<std::size_t, std::uint64_t>, std::string> recording_errors;
  std::mutex mutex;
  parallel_for(to_simulate.size(), jobs, [&](std::size_t i) {
    const AblationCell& c = to_simulate[i];
    const std::string error = simulate_ablation_recording(m, c, out, hooks);
    std::lock_guard<std::mutex> lock(mutex);
    if (!error.empty()) recording_errors[{c.recording, c.seed}] = error;
  });

  // Phase 2: the cells.
  std::vector<CellOutcome> outcomes(cells.size());
  std::atomic<std::size_t> done{0};
  parallel_for(cells.size(), jobs, [&](std::size_t i) {
    const AblationCell& c = cells[i];
    const auto e = recording_errors.find({c.recording, c.seed});
    outcomes[i] = run_ablation_cell(m, c, out, hooks, e == recording_errors.end() ? "" : e->second);
    const std::size_t n = ++done;
    std::lock_guard<std::mutex> lock(mutex);
    if (hooks.on_cell) hooks.on_cell(n, cells.size());
  });
  return outcomes;
}

void write_ablation_csv(const AblationMatrix& m, const std::vector<CellOutcome>& outcomes, const fs::path& file) {
  std::string text = "recording,variant,seed,status,seconds";
  for (const auto& metric : m.metrics) text += "," + metric;
  text += "\n";
  for (const auto& o : outcomes) {
    const char* status = o.status == CellStatus::kFailed ? "failed" : o.status == CellStatus::kResumed ? "resumed" : "done";
    text += fmt::format("{},{},{},{},{:.3f}", m.recordings[o.cell.recording].name, m.variants[o.cell.variant].name,
                        o.cell.seed, status, o.seconds);
    for (const auto& metric : m.metrics) {
      const auto it = o.metrics.find(metric);
      text += it == o.metrics.end() ? "," : fmt::format(",{}", it->second);
    }
    text += "\n";
  }
  write_text_file(file, text);
}

std::string ablation_markdown(const AblationMatrix& m, const std::vector<CellOutcome>& outcomes, const std::string& metric) {
  const std::size_t R = m.recordings.size(), V = m.variants.size();
  std::vector<std::vector<std::vector<double>>> values(R, std::vector<std::vector<double>>(V));
  std::vector<std::vector<std::size_t>> expected(R, std::vector<std::size_t>(V, 0));
  for (const auto& o : outcomes) {
    ++expected[o.cell.recording][o.cell.variant];
    const auto it = o.metrics.find(metric);
    if (o.status != CellStatus::kFailed && it != o.metrics.end())
      values[o.cell.recording][o.cell.variant].push_back(it->second);
  }
  std::string md = fmt::format("{} (mean ± std over seeds; lower is better, best per row in bold)\n\n| recording |", metric);
  for (const auto& v : m.variants) md += " " + v.name + " |";
  md += "\n|---|" + std::string() ;
  for (std::size_t v = 0; v < V; ++v) md += "---|";
  md += "\n";
  std::vector<std::vector<double>> row_means(V);  // per variant, the recordings' means (complete rows only)
  for (std::size_t r = 0; r < R; ++r) {
    std::vector<Stats> s(V);
    std::optional<std::size_t> best;
    for (std::size_t v = 0; v < V; ++v) {
      s[v] = stats(values[r][v]);
      if (s[v].n > 0 && (!best || s[v].mean < s[*best].mean)) best = v;
    }
    const bool complete = std::all_of(s.begin(), s.end(), [](const Stats& x) { return x.n > 0; });
    md += "| " + m.recordings[r].name + " |";
    for (std::size_t v = 0; v < V; ++v) {
      if (s[v].n == 0) {
        md += " failed |";
        continue;
      }
      std::string cell = s[v].n > 1 ? fmt::format("{:.4g} ± {:.2g}", s[v].mean, s[v].std) : fmt::format("{:.4g}", s[v].mean);
      if (s[v].n < expected[r][v]) cell += fmt::format(" (n={}/{})", s[v].n, expected[r][v]);
      md += " " + (best == v ? "**" + cell + "**" : cell) + " |";
      if (complete) row_means[v].push_back(s[v].mean);
    }
    md += "\n";
  }
  md += "| mean |";
  std::vector<double> means(V, NAN);
  for (std::size_t v = 0; v < V; ++v) {
    if (row_means[v].empty()) {
      md += " – |";
      continue;
    }
    means[v] = stats(row_means[v]).mean;
    md += fmt::format(" {:.4g} |", means[v]);
  }
  md += fmt::format("\n| vs {} |", m.variants[0].name);
  for (std::size_t v = 0; v < V; ++v)
    md += (std::isfinite(means[v]) && std::isfinite(means[0]) && means[0] != 0.0)
              ? fmt::format(" {:+.1f} % |", 100.0 * (means[v] - means[0]) / means[0])
              : std::string(" – |");
  md += "\n";
  return md;
}

}  // namespace navaid::experiments
