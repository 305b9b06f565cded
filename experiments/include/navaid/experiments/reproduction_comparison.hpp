#pragma once
// A paper's method comparison reproduced from an ablation study: rows = recordings, columns =
// methods (the matrix's variants; the first is the paper's proposed method), each cell the mean of
// one metric over seeds with a t confidence interval, the paper's numbers beside ours, the mean
// over recordings, and the relative change of the proposed method against each baseline over
// (recording, seed) pairs. Written as Markdown and as a long-format CSV.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "navaid/experiments/ablation.hpp"
#include "navaid/experiments/reproduction_statistics.hpp"

namespace navaid::experiments {

/// What the paper reports, keyed by our variant names (methods the paper lacks are left out).
struct PaperNumbers {
  std::string source;                               ///< e.g. "W-ROMA §VI-A, Table I"
  std::map<std::string, double> mean_by_method;     ///< the paper's mean over its sequences
  std::map<std::string, double> change_by_baseline; ///< the proposed method's relative change (fraction)
  std::size_t rows_best = 0;                        ///< rows in which the proposed method is best ...
  std::size_t rows_total = 0;                       ///< ... of this many (0 = not reported)
  std::string missing_note;                         ///< what the paper (or our copy) does not give
};

struct MethodComparison {
  std::string metric;
  double level = 0.95;
  std::vector<std::string> recordings;
  std::vector<std::string> methods;  ///< methods[0] is the proposed one
  /// [recording][method]: the metric over finished seeds (nullopt when none finished).
  std::vector<std::vector<std::optional<MeanInterval>>> cells;
  std::vector<std::vector<std::size_t>> expected;  ///< [recording][method]: seeds run
  std::vector<std::optional<std::size_t>> best;    ///< per recording, the method with the lowest mean
  /// Per method: over the seeds finished on every recording, the mean over recordings.
  std::vector<std::optional<MeanInterval>> overall;
  /// Per method (index 0 empty): the proposed method against it over the (recording, seed) pairs
  /// where both finished: change of the means (bootstrap) and mean per-pair change (paired t).
  std::vector<std::optional<RelativeChange>> change_of_means;
  std::vector<std::optional<RelativeChange>> change_per_pair;
};

struct ComparisonOptions {
  double level = 0.95;
  std::size_t bootstrap_resamples = 10000;
  std::uint64_t bootstrap_seed = 1;
};

/// Throws navaid::Error when the matrix has fewer than two variants or `metric` is not one of its
/// metrics.
MethodComparison compare_methods(const AblationMatrix& matrix, const std::vector<CellOutcome>& outcomes,
                                 const std::string& metric, const ComparisonOptions& options = {});

/// The table (`title` as its heading), the changes against each baseline and the paper's note.
std::string comparison_markdown(const MethodComparison& c, const PaperNumbers& paper, const std::string& title);

/// Columns quantity,recording,method,baseline,n,value,std,ci_low,ci_high,paper; quantity is
/// `mean` (one recording), `mean_over_recordings`, `change_of_means` or `change_per_pair`
/// (fractions); empty fields where a value does not apply or is unknown.
std::string comparison_csv(const MethodComparison& c, const PaperNumbers& paper);

}  // namespace navaid::experiments
