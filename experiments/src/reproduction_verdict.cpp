#include "navaid/experiments/reproduction_verdict.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace navaid::experiments {
namespace {

std::string pct(double fraction) { return fmt::format("{:+.1f} %", 100.0 * fraction); }

std::string finding_text(const BaselineFinding& b, const std::string& proposed, int level_pct) {
  const std::string interval =
      b.change && std::isfinite(b.change->low)
          ? fmt::format("{} ({} % CI {} to {}, {} pairs)", pct(b.change->estimate), level_pct, pct(b.change->low),
                        pct(b.change->high), b.change->pairs)
          : b.change ? pct(b.change->estimate) + " (one pair, no interval)" : std::string();
  const std::string paper = b.paper ? "the paper's " + pct(*b.paper) : std::string("no paper number");
  switch (b.finding) {
    case ChangeFinding::kNoData: return fmt::format("against {}: no finished pairs", b.baseline);
    case ChangeFinding::kReversed:
      return fmt::format("against {}: {} is **worse**: mean change {}; {}", b.baseline, proposed, interval, paper);
    case ChangeFinding::kNotSignificant:
      return fmt::format("against {}: **no significant difference**: mean change {}; {}", b.baseline, interval, paper);
    case ChangeFinding::kSmallerThanPaper:
      return fmt::format("against {}: better, but **by less than the paper**: {} vs {}", b.baseline, interval, paper);
    case ChangeFinding::kLikePaper:
      return fmt::format("against {}: better **by as much as the paper reports**: {} contains {}", b.baseline, interval,
                         paper);
    case ChangeFinding::kLargerThanPaper:
      return fmt::format("against {}: better **by more than the paper**: {} vs {}", b.baseline, interval, paper);
    case ChangeFinding::kBetterNoPaper: return fmt::format("against {}: better: {}", b.baseline, interval);
  }
  return {};
}

}  // namespace

ChangeFinding classify_change(const std::optional<RelativeChange>& change, std::optional<double> paper) {
  if (!change || !std::isfinite(change->low) || !std::isfinite(change->high)) return ChangeFinding::kNoData;
  if (change->low > 0.0) return ChangeFinding::kReversed;
  if (change->high >= 0.0) return ChangeFinding::kNotSignificant;
  if (!paper) return ChangeFinding::kBetterNoPaper;
  // Changes are negative: the paper's below our interval is a larger reduction than ours.
  if (*paper < change->low) return ChangeFinding::kSmallerThanPaper;
  if (*paper > change->high) return ChangeFinding::kLargerThanPaper;
  return ChangeFinding::kLikePaper;
}

Verdict judge_comparison(const MethodComparison& c, const PaperNumbers& paper) {
  Verdict v;
  const std::size_t V = c.methods.size();
  v.complete = std::all_of(c.overall.begin(), c.overall.end(), [](const auto& o) { return o.has_value(); });
  if (v.complete) {
    v.lowest_mean = true;
    for (std::size_t m = 1; m < V; ++m) v.lowest_mean = v.lowest_mean && c.overall[0]->mean < c.overall[m]->mean;
  }
  for (std::size_t r = 0; r < c.recordings.size(); ++r) {
    if (!c.best[r]) continue;
    ++v.rows;
    v.rows_best += *c.best[r] == 0;
  }
  bool all_better = V > 1, all_like = V > 1;
  for (std::size_t m = 1; m < V; ++m) {
    BaselineFinding b;
    b.baseline = c.methods[m];
    b.change = m < c.change_of_means.size() ? c.change_of_means[m] : std::nullopt;
    if (const auto it = paper.change_by_baseline.find(b.baseline); it != paper.change_by_baseline.end()) b.paper = it->second;
    b.finding = classify_change(b.change, b.paper);
    const bool better = b.finding == ChangeFinding::kSmallerThanPaper || b.finding == ChangeFinding::kLikePaper ||
                        b.finding == ChangeFinding::kLargerThanPaper || b.finding == ChangeFinding::kBetterNoPaper;
    all_better = all_better && better;
    all_like = all_like && b.finding == ChangeFinding::kLikePaper;
    v.baselines.push_back(b);
  }
  v.ordering_holds = v.complete && v.lowest_mean && all_better;
  v.size_like_paper = all_like;
  return v;
}

std::string verdict_markdown(const Verdict& v, const MethodComparison& c, const PaperNumbers& paper) {
  const int level_pct = static_cast<int>(std::lround(100.0 * c.level));
  const std::string& proposed = c.methods.front();
  std::string md = "# Verdict\n\n";
  md += fmt::format("**Ordering: {}.** ", v.ordering_holds ? "holds" : "does not hold");
  if (!v.complete) {
    md += "Some method has no mean over all recordings (failed cells), so the ordering cannot be confirmed.";
  } else {
    std::vector<std::size_t> order(c.methods.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return c.overall[a]->mean < c.overall[b]->mean; });
    md += "Mean " + c.metric + " over recordings, lowest first: ";
    for (std::size_t i = 0; i < order.size(); ++i)
      md += fmt::format("{}{} {:.4f}", i ? " < " : "", c.methods[order[i]], c.overall[order[i]]->mean);
    md += ".";
  }
  // The paper's own order, for the methods it reports.
  std::vector<std::pair<double, std::string>> reported;
  for (const auto& name : c.methods)
    if (const auto it = paper.mean_by_method.find(name); it != paper.mean_by_method.end()) reported.push_back({it->second, name});
  std::sort(reported.begin(), reported.end());
  if (reported.size() > 1) {
    md += " Paper: ";
    for (std::size_t i = 0; i < reported.size(); ++i)
      md += fmt::format("{}{} {:.3f}", i ? " < " : "", reported[i].second, reported[i].first);
    md += ".";
  }
  md += fmt::format(" {} has the lowest mean on {} of {} recordings", proposed, v.rows_best, v.rows);
  md += paper.rows_total ? fmt::format(" (paper: {} of {}).\n\n", paper.rows_best, paper.rows_total) : ".\n\n";

  md += fmt::format("**Size of the improvement: {}.**\n\n",
                    v.size_like_paper ? "like the paper's" : "not like the paper's (details below)");
  for (const auto& b : v.baselines) md += "- " + finding_text(b, proposed, level_pct) + "\n";
  md += fmt::format("\nChanges are of the mean over (recording, seed) pairs, {} vs baseline, with percentile bootstrap "
                    "intervals; \"like the paper\" means the interval contains the paper's number.\n",
                    proposed);
  return md;
}

}  // namespace navaid::experiments
