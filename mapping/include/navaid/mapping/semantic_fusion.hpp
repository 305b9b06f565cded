#pragma once
// How a voxel's class belief absorbs one more labelled point: the swappable policy of the semantic
// OcTree (semantic_octree.hpp). Each policy has a State stored in every node, a fuse() rule and a
// read-out; the tree is a template over the policy, so a new rule is a new struct, not a new tree.
#include <array>
#include <cstdint>
#include <string_view>

#include "navaid/core/semantic_classes.hpp"

namespace navaid::mapping {

/// One labelled point's vote: the segmentation's class and its probability of being right.
struct SemanticObservation {
  SemanticClass semantic = SemanticClass::kUnlabeled;
  float probability = 0.0f;  ///< in [0, 1]
};

/// What a voxel believes: its class and the confidence of that class.
struct SemanticBelief {
  SemanticClass semantic = SemanticClass::kUnlabeled;
  float probability = 0.0f;
};

/// eLabrador's rule (after Semantic SLAM's max fusion): same class, average the confidences;
/// different class, keep the more confident one and discount it for the disagreement.
struct MaxFusion {
  static constexpr std::string_view kName = "max";
  struct Params {
    float disagreement_discount = 0.9f;  ///< in (0, 1]
  };
  struct State {
    std::uint8_t semantic = 0;  ///< SemanticClass id; 0 (unlabeled) until a labelled point arrives
    /// Named padding: the node is written to .ot files byte for byte, and unnamed padding would
    /// carry whatever the heap held (a map file that differs between identical runs).
    std::uint8_t reserved[3] = {0, 0, 0};
    float probability = 0.0f;
    bool operator==(const State& o) const { return semantic == o.semantic && probability == o.probability; }
  };
  static void fuse(State& s, const SemanticObservation& obs, const Params& params);
  static SemanticBelief belief(const State& s) {
    return {static_cast<SemanticClass>(s.semantic), s.probability};
  }
};

/// Ablation variant: a recursive Bayes filter over all classes. An observation of class c with
/// probability p has likelihood p for c and (1 - p) / (K - 1) for every other class; the voxel
/// keeps log posteriors relative to the best class, floored at log_floor so that a voxel that
/// changed class (a car that left, a person that stood still) can still come back.
struct BayesianHistogramFusion {
  static constexpr std::string_view kName = "bayes";
  struct Params {
    float log_floor = -13.8f;  ///< ln(1e-6): the least a class can fall behind the best
  };
  struct State {
    std::array<float, kNumSemanticClasses> log_posterior{};  ///< all 0: uniform (no vote yet)
    std::uint16_t votes = 0;
    std::uint16_t reserved = 0;  ///< named padding (see MaxFusion::State)
    bool operator==(const State& o) const { return votes == o.votes && log_posterior == o.log_posterior; }
  };
  static void fuse(State& s, const SemanticObservation& obs, const Params& params);
  static SemanticBelief belief(const State& s);
};

// The states are written to .ot files byte for byte: no unnamed padding.
static_assert(sizeof(MaxFusion::State) == 1 + 3 + sizeof(float), "MaxFusion::State has padding");
static_assert(sizeof(BayesianHistogramFusion::State) == kNumSemanticClasses * sizeof(float) + 2 * sizeof(std::uint16_t),
              "BayesianHistogramFusion::State has padding");

}  // namespace navaid::mapping
