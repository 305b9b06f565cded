#pragma once
// Does a reproduced comparison agree with the paper? Two questions, answered from the numbers:
// the ordering (is the proposed method's mean the lowest, and is it lower than each baseline with
// confidence: the change's interval below zero) and the size (does the interval of the change of
// the means contain the paper's relative change, or is ours clearly smaller or larger).
#include <optional>
#include <string>
#include <vector>

#include "navaid/experiments/reproduction_comparison.hpp"

namespace navaid::experiments {

enum class ChangeFinding {
  kNoData,          ///< no pair finished
  kReversed,        ///< the proposed method is worse with confidence (interval above 0)
  kNotSignificant,  ///< the interval contains 0
  kSmallerThanPaper,  ///< better with confidence, but the paper's change is below the interval
  kLikePaper,         ///< the interval contains the paper's change
  kLargerThanPaper,   ///< better with confidence, by more than the paper reports
  kBetterNoPaper,     ///< better with confidence; the paper gives no number to compare
};

struct BaselineFinding {
  std::string baseline;
  std::optional<RelativeChange> change;  ///< of the means
  std::optional<double> paper;
  ChangeFinding finding = ChangeFinding::kNoData;
};

struct Verdict {
  bool complete = false;        ///< every method has a mean over recordings
  bool lowest_mean = false;     ///< the proposed method's mean over recordings is the lowest
  std::size_t rows_best = 0;    ///< recordings where the proposed method has the lowest mean
  std::size_t rows = 0;         ///< recordings with at least one finished cell
  bool ordering_holds = false;  ///< lowest mean and better with confidence than every baseline
  bool size_like_paper = false; ///< every baseline's change is kLikePaper
  std::vector<BaselineFinding> baselines;
};

ChangeFinding classify_change(const std::optional<RelativeChange>& change, std::optional<double> paper);

Verdict judge_comparison(const MethodComparison& c, const PaperNumbers& paper);

/// A short text: the answer to both questions with the numbers behind it.
std::string verdict_markdown(const Verdict& v, const MethodComparison& c, const PaperNumbers& paper);

}  // namespace navaid::experiments
