#include "navaid/experiments/reproduction_comparison.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "navaid/core/errors.hpp"

namespace navaid::experiments {
namespace {

std::optional<double> paper_value(const std::map<std::string, double>& m, const std::string& key) {
  const auto it = m.find(key);
  return it == m.end() ? std::nullopt : std::optional<double>(it->second);
}

std::string number(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : std::string(); }

std::string interval_text(const MeanInterval& m) {
  if (m.n < 2) return fmt::format("{:.4f} (n=1)", m.mean);
  return fmt::format("{:.4f} [{:.4f}, {:.4f}]", m.mean, m.low, m.high);
}

std::string percent(double fraction) { return fmt::format("{:+.1f} %", 100.0 * fraction); }

std::string change_text(const std::optional<RelativeChange>& c) {
  if (!c) return "–";
  if (!std::isfinite(c->low)) return percent(c->estimate) + " (1 pair)";
  return fmt::format("{} [{:+.1f}, {:+.1f}]", percent(c->estimate), 100.0 * c->low, 100.0 * c->high);
}

}  // namespace

MethodComparison compare_methods(const AblationMatrix& m, const std::vector<CellOutcome>& outcomes,
                                 const std::string& metric, const ComparisonOptions& options) {
  if (m.variants.size() < 2) throw Error("a method comparison needs at least two variants (the proposed method first)");
  if (std::find(m.metrics.begin(), m.metrics.end(), metric) == m.metrics.end())
    throw Error("metric '" + metric + "' is not among the matrix's metrics");
  const std::size_t R = m.recordings.size(), V = m.variants.size();
  MethodComparison c;
  c.metric = metric;
  c.level = options.level;
  for (const auto& r : m.recordings) c.recordings.push_back(r.name);
  for (const auto& v : m.variants) c.methods.push_back(v.name);

  // value[r][v][seed]
  std::vector<std::vector<std::map<std::uint64_t, double>>> value(R, std::vector<std::map<std::uint64_t, double>>(V));
  c.expected.assign(R, std::vector<std::size_t>(V, 0));
  for (const auto& o : outcomes) {
    ++c.expected[o.cell.recording][o.cell.variant];
    const auto it = o.metrics.find(metric);
    if (o.status != CellStatus::kFailed && it != o.metrics.end() && std::isfinite(it->second))
      value[o.cell.recording][o.cell.variant][o.cell.seed] = it->second;
  }

  c.cells.assign(R, std::vector<std::optional<MeanInterval>>(V));
  c.best.assign(R, std::nullopt);
  for (std::size_t r = 0; r < R; ++r) {
    for (std::size_t v = 0; v < V; ++v) {
      std::vector<double> xs;
      for (const auto& [seed, x] : value[r][v]) xs.push_back(x);
      if (xs.empty()) continue;
      c.cells[r][v] = mean_interval(xs, options.level);
      if (!c.best[r] || c.cells[r][v]->mean < c.cells[r][*c.best[r]]->mean) c.best[r] = v;
    }
  }

  c.overall.assign(V, std::nullopt);
  for (std::size_t v = 0; v < V; ++v) {
    std::vector<double> per_seed;  // the mean over recordings, one per seed finished everywhere
    for (const auto& [seed, x0] : value[0][v]) {
      double sum = 0.0;
      bool all = true;
      for (std::size_t r = 0; r < R && all; ++r) {
        const auto it = value[r][v].find(seed);
        all = it != value[r][v].end();
        if (all) sum += it->second;
      }
      if (all) per_seed.push_back(sum / static_cast<double>(R));
    }
    if (!per_seed.empty()) c.overall[v] = mean_interval(per_seed, options.level);
  }

  c.change_of_means.assign(V, std::nullopt);
  c.change_per_pair.assign(V, std::nullopt);
  for (std::size_t v = 1; v < V; ++v) {
    std::vector<double> proposed, baseline;
    for (std::size_t r = 0; r < R; ++r)
      for (const auto& [seed, x] : value[r][0])
        if (const auto it = value[r][v].find(seed); it != value[r][v].end() && it->second > 0.0) {
          proposed.push_back(x);
          baseline.push_back(it->second);
        }
    if (proposed.empty()) continue;
    c.change_of_means[v] =
        relative_change_bootstrap(proposed, baseline, options.level, options.bootstrap_resamples, options.bootstrap_seed);
    c.change_per_pair[v] = relative_change_paired_t(proposed, baseline, options.level);
  }
  return c;
}

std::string comparison_markdown(const MethodComparison& c, const PaperNumbers& paper, const std::string& title) {
  const std::size_t V = c.methods.size();
  const int pct = static_cast<int>(std::lround(100.0 * c.level));
  std::string md = fmt::format("### {}\n\n{}: mean over seeds [{} % t confidence interval]; lower is better, the best "
                               "mean of each row in bold; \"paper\" columns: {}.\n\n| recording |",
                               title, c.metric, pct, paper.source);
  std::string rule = "|---|";
  for (const auto& name : c.methods) {
    md += fmt::format(" {} | paper |", name);
    rule += "---|---|";
  }
  md += "\n" + rule + "\n";
  for (std::size_t r = 0; r < c.recordings.size(); ++r) {
    md += "| " + c.recordings[r] + " |";
    for (std::size_t v = 0; v < V; ++v) {
      const auto& cell = c.cells[r][v];
      std::string text = cell ? interval_text(*cell) : std::string("failed");
      if (cell && cell->n < c.expected[r][v]) text += fmt::format(" (n={}/{})", cell->n, c.expected[r][v]);
      if (c.best[r] == v) text = "**" + text + "**";
      md += " " + text + " | – |";
    }
    md += "\n";
  }
  md += "| **mean over recordings** |";
  for (std::size_t v = 0; v < V; ++v) {
    const auto p = paper_value(paper.mean_by_method, c.methods[v]);
    md += " " + (c.overall[v] ? interval_text(*c.overall[v]) : std::string("–")) + " | " +
          (p ? fmt::format("{:.3f}", *p) : std::string("–")) + " |";
  }
  md += "\n\n";
  if (!paper.missing_note.empty()) md += paper.missing_note + "\n\n";

  md += fmt::format("{} against each baseline (negative = {} lower), over the (recording, seed) pairs where both "
                    "finished:\n\n| baseline | pairs | change of the mean [{} % bootstrap CI] | mean per-pair change "
                    "[{} % paired-t CI] | paper |\n|---|---|---|---|---|\n",
                    c.methods[0], c.methods[0], pct, pct);
  for (std::size_t v = 1; v < V; ++v) {
    const auto p = paper_value(paper.change_by_baseline, c.methods[v]);
    md += fmt::format("| {} | {} | {} | {} | {} |\n", c.methods[v], c.change_of_means[v] ? c.change_of_means[v]->pairs : 0,
                      change_text(c.change_of_means[v]), change_text(c.change_per_pair[v]),
                      p ? percent(*p) : std::string("–"));
  }
  return md;
}

std::string comparison_csv(const MethodComparison& c, const PaperNumbers& paper) {
  std::string csv = "quantity,recording,method,baseline,n,value,std,ci_low,ci_high,paper\n";
  auto interval_row = [&](const char* quantity, const std::string& recording, std::size_t v,
                          const std::optional<MeanInterval>& m, std::optional<double> p) {
    csv += fmt::format("{},{},{},,{},{},{},{},{},{}\n", quantity, recording, c.methods[v], m ? m->n : 0,
                       m ? number(m->mean) : "", m && m->n > 1 ? number(m->std) : "", m ? number(m->low) : "",
                       m ? number(m->high) : "", p ? number(*p) : "");
  };
  for (std::size_t r = 0; r < c.recordings.size(); ++r)
    for (std::size_t v = 0; v < c.methods.size(); ++v) interval_row("mean", c.recordings[r], v, c.cells[r][v], std::nullopt);
  for (std::size_t v = 0; v < c.methods.size(); ++v)
    interval_row("mean_over_recordings", "", v, c.overall[v], paper_value(paper.mean_by_method, c.methods[v]));
  for (std::size_t v = 1; v < c.methods.size(); ++v) {
    const auto p = paper_value(paper.change_by_baseline, c.methods[v]);
    for (const auto& [quantity, change] : {std::pair<const char*, const std::optional<RelativeChange>&>{"change_of_means", c.change_of_means[v]},
                                           {"change_per_pair", c.change_per_pair[v]}})
      csv += fmt::format("{},,{},{},{},{},,{},{},{}\n", quantity, c.methods[0], c.methods[v], change ? change->pairs : 0,
                         change ? number(change->estimate) : "", change ? number(change->low) : "",
                         change ? number(change->high) : "", quantity == std::string("change_of_means") && p ? number(*p) : "");
  }
  return csv;
}

}  // namespace navaid::experiments
