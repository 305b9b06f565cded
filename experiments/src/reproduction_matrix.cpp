#include "navaid/experiments/reproduction_matrix.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "navaid/core/errors.hpp"

namespace navaid::experiments {

namespace fs = std::filesystem;

namespace {

nlohmann::json recording_spec(const AblationRecording& r) {
  if (!r.simulated()) return {{"path", r.path->string()}};
  return {{"scenario", r.scenario}, {"set", r.simulate_overrides}};
}

// A cell's result depends on the run overrides and the variant's, in this order.
nlohmann::json variant_spec(const AblationMatrix& m, const AblationVariant& v) {
  return {{"run", m.run_overrides}, {"set", v.overrides}};
}

std::size_t remove_folder(const fs::path& p) {
  std::error_code ec;
  if (!fs::exists(p, ec)) return 0;
  fs::remove_all(p, ec);
  if (ec) throw IoError(p.string(), "cannot remove a stale result: " + ec.message());
  return 1;
}

}  // namespace

void set_seed_count(AblationMatrix& m, std::size_t count) {
  if (count == 0) return;
  if (count <= m.seeds.size()) {
    m.seeds.resize(count);
    return;
  }
  std::uint64_t next = *std::max_element(m.seeds.begin(), m.seeds.end()) + 1;
  while (m.seeds.size() < count) m.seeds.push_back(next++);
}

void apply_quick_subset(AblationMatrix& m, const QuickSubset& quick, const std::string& source) {
  std::vector<AblationRecording> kept;
  for (const auto& name : quick.recordings)
    if (std::none_of(m.recordings.begin(), m.recordings.end(), [&](const auto& r) { return r.name == name; }))
      throw ConfigError(source, "recordings", "the quick subset needs a recording named '" + name + "'");
  for (auto r : m.recordings) {
    if (std::find(quick.recordings.begin(), quick.recordings.end(), r.name) == quick.recordings.end()) continue;
    r.name += quick.suffix;
    if (r.simulated())
      r.simulate_overrides.insert(r.simulate_overrides.end(), quick.simulate_overrides.begin(),
                                  quick.simulate_overrides.end());
    kept.push_back(std::move(r));
  }
  m.recordings = std::move(kept);
  set_seed_count(m, std::min(quick.seeds, m.seeds.size()));
}

std::size_t remove_stale_results(const AblationMatrix& m, const fs::path& out) {
  const fs::path file = out / "matrix-state.json";
  nlohmann::json state = {{"recordings", nlohmann::json::object()}, {"variants", nlohmann::json::object()}};
  bool had_state = false;
  if (fs::exists(file)) {
    std::ifstream in(file);
    const auto j = nlohmann::json::parse(in, nullptr, false);
    // A damaged state file cannot vouch for any result: treat it as a fresh folder's.
    if (!j.is_discarded() && j.is_object() && j.contains("recordings") && j.contains("variants")) {
      state = j;
      had_state = true;
    }
  }
  std::size_t removed = 0;
  for (const auto& r : m.recordings) {
    const auto spec = recording_spec(r);
    auto& old = state["recordings"][r.name];
    if (had_state && !old.is_null() && old != spec) {
      removed += remove_folder(out / "recordings" / r.name);
      removed += remove_folder(out / "cells" / r.name);
    }
    old = spec;
  }
  for (const auto& v : m.variants) {
    const auto spec = variant_spec(m, v);
    auto& old = state["variants"][v.name];
    if (had_state && !old.is_null() && old != spec && fs::exists(out / "cells"))
      for (const auto& rec : fs::directory_iterator(out / "cells")) removed += remove_folder(rec.path() / v.name);
    old = spec;
  }
  fs::create_directories(out);
  std::ofstream o(file, std::ios::binary);
  o << state.dump(2) << "\n";
  if (!o) throw IoError(file.string(), "cannot write");
  return removed;
}

}  // namespace navaid::experiments
