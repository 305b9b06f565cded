#include "navaid/mapping/semantic_fusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace navaid::mapping {

void MaxFusion::fuse(State& s, const SemanticObservation& obs, const Params& params) {
  if (obs.semantic == SemanticClass::kUnlabeled) return;  // geometry-only points carry no vote
  const auto id = static_cast<std::uint8_t>(obs.semantic);
  if (s.semantic == 0) {
    s.semantic = id;
    s.probability = obs.probability;
  } else if (s.semantic == id) {
    s.probability = 0.5f * (s.probability + obs.probability);
  } else if (obs.probability > s.probability) {
    s.semantic = id;
    s.probability = obs.probability * params.disagreement_discount;
  } else {
    s.probability *= params.disagreement_discount;
  }
}

void BayesianHistogramFusion::fuse(State& s, const SemanticObservation& obs, const Params& params) {
  if (obs.semantic == SemanticClass::kUnlabeled) return;
  constexpr float kK = static_cast<float>(kNumSemanticClasses - 1);  // labelled classes
  // Keep both likelihoods away from 0 and 1 so that one vote never decides for ever.
  const float p = std::clamp(obs.probability, 1e-3f, 1.0f - 1e-3f);
  const float log_hit = std::log(p);
  const float log_other = std::log((1.0f - p) / (kK - 1.0f));
  const auto c = static_cast<std::size_t>(obs.semantic);
  float best = -std::numeric_limits<float>::infinity();
  for (std::size_t k = 1; k < kNumSemanticClasses; ++k) {
    s.log_posterior[k] += (k == c) ? log_hit : log_other;
    best = std::max(best, s.log_posterior[k]);
  }
  for (std::size_t k = 1; k < kNumSemanticClasses; ++k) {
    s.log_posterior[k] = std::max(s.log_posterior[k] - best, params.log_floor);
  }
  if (s.votes < std::numeric_limits<std::uint16_t>::max()) ++s.votes;
}

SemanticBelief BayesianHistogramFusion::belief(const State& s) {
  if (s.votes == 0) return {};
  std::size_t best = 1;
  double sum = 0.0;
  for (std::size_t k = 1; k < kNumSemanticClasses; ++k) {
    if (s.log_posterior[k] > s.log_posterior[best]) best = k;
    sum += std::exp(static_cast<double>(s.log_posterior[k]));
  }
  const double p = std::exp(static_cast<double>(s.log_posterior[best])) / sum;
  return {static_cast<SemanticClass>(best), static_cast<float>(p)};
}

}  // namespace navaid::mapping
