#pragma once
// Errors of a semantic segmentation network (eLabrador runs a Mapillary-trained one), applied to
// the simulator's true label image (docs/semantic-classes.md, "Label confusion model").
//
// Confusion matrix M[t][p] = P(predicted p | true t): the diagonal is the per-class accuracy a_t;
// the error mass 1 - a_t is spread over the plausible confusions of t in proportion to their
// weights (default_label_confusions(), undirected pairs, and one_way_confusions, where only a is
// taken for b); a row override replaces a whole row.
// `unlabeled` (id 0) is never predicted and passes through (row 0 = identity).
//
// Spatial coherence (a network errs on regions, not on single pixels):
//  1. the image is cut into cell_size_px square cells, the grid shifted by a random offset per
//     frame; the pixels of one true label inside one cell form a group that gets one predicted
//     label p ~ M[t][.] and one confidence;
//  2. boundary erosion: a pixel within boundary_width_px (Chebyshev) of a pixel of another
//     (labelled) class takes, with boundary_probability, the step-1 prediction of its nearest such
//     pixel (Euclidean; ties in scan order), and draws its own confidence.
// Errors of step 2 come on top of M: the matrix describes step 1.
//
// Confidence (the probability the network reports for its label) is calibrated: for a pixel of
// true class t, with alpha_t = kappa a_t and beta_t = kappa (1 - a_t) (kappa =
// confidence_concentration, a_t capped at 1 - 1e-6),
//   correct prediction: c ~ Beta(alpha_t + 1, beta_t),   wrong prediction: c ~ Beta(alpha_t, beta_t + 1).
// Then the marginal of c is Beta(alpha_t, beta_t) and P(correct | c, t) = c exactly: among step-1
// predictions reported with confidence c, a fraction c is right; E[c | correct] - E[c | wrong] =
// 1 / (kappa + 1). Eroded pixels make the network over-confident near edges, as real ones are.
// Unlabeled pixels have confidence 1.
//
// posterior() is Bayes on this generative model (step 1):
//   P(t | p, c) ∝ prior_t M[t][p] Beta_pdf(c; correct or wrong parameters of t).
//
// Every frame's draws come from one engine seeded by (seed, frame_index) (frame_rng.hpp).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "navaid/core/image.hpp"
#include "navaid/simulation/semantic_classes.hpp"

namespace navaid::simulation {

/// One probability (or weight) per class, indexed by class id.
using ClassProbabilities = std::array<double, kNumSemanticClasses>;
/// M[true][predicted]; rows sum to 1.
using ConfusionMatrix = std::array<ClassProbabilities, kNumSemanticClasses>;

/// A plausible confusion between two labelled classes, both ways, with a relative weight (> 0).
struct ConfusionPair {
  SemanticClass a;
  SemanticClass b;
  double weight = 1.0;
};

/// Replaces the row of `true_class` by `predicted` (non-negative, normalized to sum 1).
struct ConfusionRowOverride {
  SemanticClass true_class;
  ClassProbabilities predicted{};
};

/// Default per-class accuracy (docs/semantic-classes.md): 0.9, higher for large "stuff" classes,
/// lower for small and thin ones; 1 for unlabeled.
ClassProbabilities default_label_accuracy();
/// 1 / kNumSemanticClasses for every class.
ClassProbabilities uniform_class_prior();
/// Default plausible confusions (docs/semantic-classes.md); e.g. floor <-> ceiling is not among them.
std::vector<ConfusionPair> default_label_confusions();
/// Default one-way confusions (a taken for b, b's row left alone): target-object -> table, a small
/// object taken for the table it stands on, while a table is not taken for the object.
std::vector<ConfusionPair> default_one_way_label_confusions();

struct LabelConfusionConfig {
  ClassProbabilities accuracy = default_label_accuracy();  ///< a_t in (0, 1]; unlabeled must be 1
  std::vector<ConfusionPair> confusions = default_label_confusions();
  std::vector<ConfusionPair> one_way_confusions = default_one_way_label_confusions();
  std::vector<ConfusionRowOverride> row_overrides;
  /// Prior over true classes for posterior() (>= 0, not all 0; normalized); uniform by default.
  ClassProbabilities prior = uniform_class_prior();
  int cell_size_px = 16;             ///< side of the error cells, [1, 4096]
  int boundary_width_px = 1;         ///< k of the boundary erosion, [0, 16]
  double boundary_probability = 0.3;  ///< [0, 1]; 0 (or k = 0) switches erosion off
  double confidence_concentration = 4.0;  ///< kappa, (0, 1e4]; smaller = more spread confidence
  bool noise = true;                 ///< false: prediction = truth, confidence 1
};

/// Throws ConfigError(source, key, ...) naming the first bad key (e.g. "accuracy.pole",
/// "confusions[3].weight", "one_way_confusions[0]", "row_overrides[0]", "prior.road", "cell_size_px").
void validate(const LabelConfusionConfig& config, const std::string& source = "label_confusion");

/// The matrix of a config (validated first).
ConfusionMatrix build_confusion_matrix(const LabelConfusionConfig& config);

/// Output of the simulated network.
struct LabelPrediction {
  ImageU8 labels;       ///< predicted SemanticClass ids
  ImageF32 confidence;  ///< reported probability of the predicted label, in (0, 1]
};

class LabelConfusionModel {
 public:
  /// Validates the config (ConfigError) and builds the matrix.
  explicit LabelConfusionModel(LabelConfusionConfig config = {});

  /// Predicted labels and confidences of a true label image, deterministic per
  /// (seed, frame_index). std::invalid_argument when a label is not a valid class id. Const and
  /// safe to call from several threads (frames in parallel).
  LabelPrediction apply(const ImageU8& true_labels, std::uint64_t seed, std::uint64_t frame_index) const;
  /// Same, reusing the buffers of `out`.
  void apply(const ImageU8& true_labels, std::uint64_t seed, std::uint64_t frame_index, LabelPrediction& out) const;

  /// P(true | predicted) ∝ prior_t M[t][p]. When no class can produce `predicted` under the
  /// prior, the one-hot vector of `predicted` (the model carries no evidence against it).
  ClassProbabilities posterior(SemanticClass predicted) const;
  /// P(true | predicted, confidence); confidence in [0, 1] (std::invalid_argument otherwise) is
  /// clamped to [1e-9, 1 - 1e-9] so that densities stay finite. Same fallback as above.
  ClassProbabilities posterior(SemanticClass predicted, double confidence) const;

  /// Density of the reported confidence c for a pixel of true class t predicted (in)correctly.
  double confidence_density(SemanticClass true_class, bool correct, double c) const;
  /// E[c | t, correct] = (alpha_t + 1) / (kappa + 1), E[c | t, wrong] = alpha_t / (kappa + 1).
  double mean_confidence(SemanticClass true_class, bool correct) const;

  const ConfusionMatrix& matrix() const { return matrix_; }
  double accuracy(SemanticClass c) const { return matrix_[static_cast<std::size_t>(c)][static_cast<std::size_t>(c)]; }
  const LabelConfusionConfig& config() const { return config_; }

 private:
  struct BetaParams {
    double a = 1, b = 1;
    double log_norm = 0;  ///< -log B(a, b)
  };
  const BetaParams& beta(std::size_t t, bool correct) const { return correct ? correct_[t] : wrong_[t]; }

  LabelConfusionConfig config_;
  ConfusionMatrix matrix_{};
  ConfusionMatrix cumulative_{};  ///< row-wise cumulative sums for sampling
  std::array<BetaParams, kNumSemanticClasses> correct_{}, wrong_{};
  ClassProbabilities prior_{};    ///< normalized
};

}  // namespace navaid::simulation
