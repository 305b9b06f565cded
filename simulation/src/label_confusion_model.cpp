#include "navaid/simulation/label_confusion_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "navaid/core/errors.hpp"
#include "navaid/simulation/frame_rng.hpp"

namespace navaid::simulation {

namespace {

constexpr std::size_t K = kNumSemanticClasses;
using C = SemanticClass;

constexpr double kMaxBetaAccuracy = 1.0 - 1e-6;  // keeps beta_t > 0 when a_t = 1
constexpr double kMinConfidence = 1e-6;          // reported confidences are in (0, 1]
constexpr double kPosteriorClamp = 1e-9;

std::size_t idx(SemanticClass c) { return static_cast<std::size_t>(c); }
std::string name(std::size_t i) { return std::string(semantic_class_name(static_cast<SemanticClass>(i))); }

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool labelled_class(SemanticClass c) { return idx(c) > 0 && idx(c) < K; }

double beta_log_norm(double a, double b) { return std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b); }

// Beta(a, b) as X / (X + Y) with X ~ Gamma(a), Y ~ Gamma(b); an all-underflow draw (both shapes
// tiny) goes to the side of the larger shape.
double sample_beta(std::mt19937_64& rng, double a, double b) {
  using Gamma = std::gamma_distribution<double>;
  Gamma gamma;
  const double x = gamma(rng, Gamma::param_type(a));
  const double y = gamma(rng, Gamma::param_type(b));
  const double c = (x + y > 0.0) ? x / (x + y) : (a >= b ? 1.0 : 0.0);
  return std::clamp(c, kMinConfidence, 1.0);
}

// Finite, non-negative, not all zero; the key of an error names the offending class.
void check_probability_vector(const std::string& source, const std::string& key, const ClassProbabilities& v,
                              bool allow_unlabeled) {
  double sum = 0.0;
  for (std::size_t i = 0; i < K; ++i) {
    if (!std::isfinite(v[i]) || v[i] < 0.0) {
      throw ConfigError(source, key + "." + name(i), "expected a finite value >= 0, found " + str(v[i]));
    }
    if (i == 0 && !allow_unlabeled && v[i] != 0.0) {
      throw ConfigError(source, key + ".unlabeled", "the network never predicts 'unlabeled': expected 0, found " + str(v[i]));
    }
    sum += v[i];
  }
  if (!(sum > 0.0)) throw ConfigError(source, key, "expected at least one value > 0, all are 0");
}

}  // namespace

ClassProbabilities default_label_accuracy() {
  ClassProbabilities a{};
  a.fill(0.9);
  auto set = [&](C c, double v) { a[idx(c)] = v; };
  set(C::kUnlabeled, 1.0);
  // Large, well-textured "stuff" and frequent objects.
  set(C::kRoad, 0.95);
  set(C::kBuilding, 0.93);
  set(C::kVegetation, 0.92);
  set(C::kCar, 0.93);
  set(C::kSky, 0.97);
  // Classes a street-scene network confuses with their surroundings.
  set(C::kTerrain, 0.85);
  set(C::kPerson, 0.85);
  set(C::kCrosswalk, 0.8);
  set(C::kWall, 0.8);
  set(C::kFence, 0.8);
  set(C::kBench, 0.8);
  set(C::kDoor, 0.8);
  set(C::kChair, 0.8);
  set(C::kTable, 0.8);
  set(C::kBusStop, 0.75);  // no Mapillary class of its own
  // Small and thin classes: lowest per-class IoU in street-scene benchmarks.
  set(C::kTrafficSign, 0.7);
  set(C::kTreeTrunk, 0.7);
  set(C::kBicycle, 0.7);
  set(C::kPole, 0.65);
  set(C::kCurb, 0.65);
  set(C::kTactilePaving, 0.6);
  set(C::kTargetObject, 0.85);  // a box-sized object: a detector-like class, mistaken for its table
  return a;
}

std::vector<ConfusionPair> default_label_confusions() {
  return {
      // Ground surfaces.
      {C::kSidewalk, C::kRoad, 3.0},
      {C::kSidewalk, C::kTactilePaving, 2.0},
      {C::kSidewalk, C::kCurb, 2.0},
      {C::kSidewalk, C::kCrosswalk, 1.0},
      {C::kSidewalk, C::kTerrain, 1.0},
      {C::kRoad, C::kCrosswalk, 2.0},
      {C::kRoad, C::kCurb, 1.0},
      {C::kRoad, C::kTerrain, 0.5},
      {C::kCrosswalk, C::kTactilePaving, 0.5},
      {C::kTerrain, C::kVegetation, 2.0},
      // Vertical structures.
      {C::kBuilding, C::kWall, 3.0},
      {C::kBuilding, C::kDoor, 1.0},
      {C::kWall, C::kDoor, 1.0},
      {C::kWall, C::kFence, 1.0},
      {C::kBuilding, C::kBusStop, 1.0},
      {C::kBusStop, C::kFence, 0.5},
      {C::kFence, C::kVegetation, 1.0},
      {C::kFence, C::kPole, 0.5},
      // Thin objects.
      {C::kPole, C::kTrafficSign, 2.0},
      {C::kPole, C::kTreeTrunk, 2.0},
      {C::kTrafficSign, C::kBuilding, 0.5},
      {C::kTreeTrunk, C::kVegetation, 2.0},
      // Furniture and movable objects.
      {C::kBench, C::kChair, 1.0},
      {C::kBench, C::kFence, 1.0},
      {C::kChair, C::kTable, 2.0},
      {C::kBench, C::kTable, 0.5},
      {C::kCar, C::kBicycle, 0.5},
      {C::kCar, C::kBuilding, 0.5},
      {C::kBicycle, C::kPerson, 1.0},
      {C::kBicycle, C::kFence, 1.0},
      {C::kPerson, C::kPole, 0.5},
      {C::kPerson, C::kCar, 0.5},
      // Sky and indoor.
      {C::kSky, C::kVegetation, 1.0},
      {C::kSky, C::kBuilding, 1.0},
      {C::kCeiling, C::kWall, 2.0},
      {C::kCeiling, C::kSky, 0.5},
      {C::kFloor, C::kWall, 0.5},
      {C::kFloor, C::kSidewalk, 1.0},
  };
}

std::vector<ConfusionPair> default_one_way_label_confusions() {
  // The hand-guidance target is taken for the table it stands on, never the other way round (so
  // the table's row stays what it was before the class existed).
  return {{C::kTargetObject, C::kTable, 1.0}};
}

ClassProbabilities uniform_class_prior() {
  ClassProbabilities p{};
  p.fill(1.0 / static_cast<double>(K));
  return p;
}

void validate(const LabelConfusionConfig& c, const std::string& source) {
  for (std::size_t t = 0; t < K; ++t) {
    const double a = c.accuracy[t];
    const std::string key = "accuracy." + name(t);
    if (t == 0) {
      if (a != 1.0) throw ConfigError(source, key, "unlabeled pixels pass through: expected 1, found " + str(a));
    } else if (!std::isfinite(a) || a <= 0.0 || a > 1.0) {
      throw ConfigError(source, key, "expected a value in (0, 1], found " + str(a));
    }
  }
  // What both kinds of confusion pair need: two labelled classes, not the same, a weight > 0.
  const auto check_pair = [&](const ConfusionPair& p, const std::string& key) {
    if (!labelled_class(p.a) || !labelled_class(p.b)) {
      throw ConfigError(source, key, "expected two labelled classes (not 'unlabeled', ids < " + std::to_string(K) + ")");
    }
    if (p.a == p.b) throw ConfigError(source, key, "a class cannot be confused with itself ('" + name(idx(p.a)) + "')");
    if (!std::isfinite(p.weight) || p.weight <= 0.0) {
      throw ConfigError(source, key + ".weight", "expected a finite value > 0, found " + str(p.weight));
    }
  };
  std::array<bool, K> has_partner{};
  for (std::size_t i = 0; i < c.confusions.size(); ++i) {
    const ConfusionPair& p = c.confusions[i];
    const std::string key = "confusions[" + std::to_string(i) + "]";
    check_pair(p, key);
    for (std::size_t j = 0; j < i; ++j) {
      const ConfusionPair& q = c.confusions[j];
      if ((q.a == p.a && q.b == p.b) || (q.a == p.b && q.b == p.a)) {
        throw ConfigError(source, key,
                          "duplicates confusions[" + std::to_string(j) + "] (" + name(idx(p.a)) + " <-> " + name(idx(p.b)) + ")");
      }
    }
    has_partner[idx(p.a)] = has_partner[idx(p.b)] = true;
  }
  for (std::size_t i = 0; i < c.one_way_confusions.size(); ++i) {
    const ConfusionPair& p = c.one_way_confusions[i];
    const std::string key = "one_way_confusions[" + std::to_string(i) + "]";
    check_pair(p, key);
    for (std::size_t j = 0; j < i; ++j) {
      const ConfusionPair& q = c.one_way_confusions[j];
      if (q.a == p.a && q.b == p.b) {
        throw ConfigError(source, key,
                          "duplicates one_way_confusions[" + std::to_string(j) + "] (" + name(idx(p.a)) + " -> " + name(idx(p.b)) + ")");
      }
    }
    for (std::size_t j = 0; j < c.confusions.size(); ++j) {
      const ConfusionPair& q = c.confusions[j];
      if ((q.a == p.a && q.b == p.b) || (q.a == p.b && q.b == p.a)) {
        throw ConfigError(source, key,
                          "duplicates confusions[" + std::to_string(j) + "] (" + name(idx(p.a)) + " <-> " + name(idx(p.b)) + ")");
      }
    }
    has_partner[idx(p.a)] = true;
  }
  std::array<bool, K> overridden{};
  for (std::size_t i = 0; i < c.row_overrides.size(); ++i) {
    const ConfusionRowOverride& o = c.row_overrides[i];
    const std::string key = "row_overrides[" + std::to_string(i) + "]";
    if (!labelled_class(o.true_class)) {
      throw ConfigError(source, key + ".true_class", "expected a labelled class (not 'unlabeled', id < " + std::to_string(K) + ")");
    }
    if (overridden[idx(o.true_class)]) {
      throw ConfigError(source, key, "a second override of the row of '" + name(idx(o.true_class)) + "'");
    }
    overridden[idx(o.true_class)] = true;
    check_probability_vector(source, key, o.predicted, false);
    if (!(o.predicted[idx(o.true_class)] > 0.0)) {
      throw ConfigError(source, key + "." + name(idx(o.true_class)), "the accuracy (diagonal) must be > 0, found 0");
    }
  }
  for (std::size_t t = 1; t < K; ++t) {
    if (c.accuracy[t] < 1.0 && !has_partner[t] && !overridden[t]) {
      throw ConfigError(source, "accuracy." + name(t),
                        "accuracy " + str(c.accuracy[t]) + " < 1 leaves error mass but '" + name(t) +
                            "' has no plausible confusion (add one to confusions or override its row)");
    }
  }
  check_probability_vector(source, "prior", c.prior, true);
  if (c.cell_size_px < 1 || c.cell_size_px > 4096) {
    throw ConfigError(source, "cell_size_px", "expected an integer in [1, 4096], found " + std::to_string(c.cell_size_px));
  }
  if (c.boundary_width_px < 0 || c.boundary_width_px > 16) {
    throw ConfigError(source, "boundary_width_px", "expected an integer in [0, 16], found " + std::to_string(c.boundary_width_px));
  }
  if (!std::isfinite(c.boundary_probability) || c.boundary_probability < 0.0 || c.boundary_probability > 1.0) {
    throw ConfigError(source, "boundary_probability", "expected a value in [0, 1], found " + str(c.boundary_probability));
  }
  if (!std::isfinite(c.confidence_concentration) || c.confidence_concentration <= 0.0 || c.confidence_concentration > 1e4) {
    throw ConfigError(source, "confidence_concentration", "expected a value in (0, 1e4], found " + str(c.confidence_concentration));
  }
}

ConfusionMatrix build_confusion_matrix(const LabelConfusionConfig& c) {
  validate(c);
  ConfusionMatrix m{};
  for (std::size_t t = 0; t < K; ++t) m[t][t] = c.accuracy[t];
  // Error mass of each row spread over its partners by weight.
  ClassProbabilities partner_weight{};
  for (const auto& p : c.confusions) {
    partner_weight[idx(p.a)] += p.weight;
    partner_weight[idx(p.b)] += p.weight;
  }
  for (const auto& p : c.one_way_confusions) partner_weight[idx(p.a)] += p.weight;
  for (const auto& p : c.confusions) {
    const std::size_t a = idx(p.a), b = idx(p.b);
    m[a][b] += (1.0 - c.accuracy[a]) * p.weight / partner_weight[a];
    m[b][a] += (1.0 - c.accuracy[b]) * p.weight / partner_weight[b];
  }
  for (const auto& p : c.one_way_confusions) {
    const std::size_t a = idx(p.a), b = idx(p.b);
    m[a][b] += (1.0 - c.accuracy[a]) * p.weight / partner_weight[a];
  }
  for (const auto& o : c.row_overrides) {
    double sum = 0.0;
    for (double v : o.predicted) sum += v;
    for (std::size_t p = 0; p < K; ++p) m[idx(o.true_class)][p] = o.predicted[p] / sum;
  }
  return m;
}

LabelConfusionModel::LabelConfusionModel(LabelConfusionConfig config)
    : config_(std::move(config)), matrix_(build_confusion_matrix(config_)) {
  const double kappa = config_.confidence_concentration;
  for (std::size_t t = 0; t < K; ++t) {
    double acc = 0.0;
    for (std::size_t p = 0; p < K; ++p) {
      acc += matrix_[t][p];
      cumulative_[t][p] = acc;
    }
    cumulative_[t][K - 1] = std::numeric_limits<double>::infinity();  // rounding never falls off the row
    const double a = std::min(matrix_[t][t], kMaxBetaAccuracy);
    const double alpha = kappa * a, beta = kappa * (1.0 - a);
    correct_[t] = {alpha + 1.0, beta, beta_log_norm(alpha + 1.0, beta)};
    wrong_[t] = {alpha, beta + 1.0, beta_log_norm(alpha, beta + 1.0)};
  }
  double sum = 0.0;
  for (double v : config_.prior) sum += v;
  for (std::size_t t = 0; t < K; ++t) prior_[t] = config_.prior[t] / sum;
}

LabelPrediction LabelConfusionModel::apply(const ImageU8& true_labels, std::uint64_t seed, std::uint64_t frame_index) const {
  LabelPrediction out;
  apply(true_labels, seed, frame_index, out);
  return out;
}

void LabelConfusionModel::apply(const ImageU8& truth, std::uint64_t seed, std::uint64_t frame_index,
                                LabelPrediction& out) const {
  const int w = truth.width, h = truth.height;
  if (truth.channels != 1) {
    throw std::invalid_argument("LabelConfusionModel::apply: expected a one-channel label image, found " +
                                std::to_string(truth.channels) + " channels");
  }
  for (std::size_t i = 0; i < truth.pixels.size(); ++i) {
    if (!is_valid_semantic_id(truth.pixels[i])) {
      throw std::invalid_argument("LabelConfusionModel::apply: label " + std::to_string(truth.pixels[i]) + " at pixel (" +
                                  std::to_string(i % static_cast<std::size_t>(w)) + ", " +
                                  std::to_string(i / static_cast<std::size_t>(w)) + ") is not a semantic class id");
    }
  }
  out.labels = truth;
  out.confidence = ImageF32(w, h, 1, 1.0f);
  if (!config_.noise || truth.pixels.empty()) return;

  std::mt19937_64 rng = frame_rng(seed, frame_index, FrameNoiseStream::kLabels);
  auto draw_confidence = [&](std::size_t t, bool correct) {
    const BetaParams& b = beta(t, correct);
    return static_cast<float>(sample_beta(rng, b.a, b.b));
  };

  // 1. One draw per (cell, true label) group, cells visited in raster order.
  const int cell = config_.cell_size_px;
  const int ox = static_cast<int>(rng() % static_cast<std::uint64_t>(cell));
  const int oy = static_cast<int>(rng() % static_cast<std::uint64_t>(cell));
  std::array<std::int64_t, K> group_of{};  // id of the group a class last drew in
  group_of.fill(-1);
  std::array<std::uint8_t, K> group_label{};
  std::array<float, K> group_conf{};
  std::int64_t group = 0;
  for (int y0 = -oy; y0 < h; y0 += cell) {
    for (int x0 = -ox; x0 < w; x0 += cell, ++group) {
      for (int y = std::max(y0, 0); y < std::min(y0 + cell, h); ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * w;
        for (int x = std::max(x0, 0); x < std::min(x0 + cell, w); ++x) {
          const std::size_t t = truth.pixels[row + x];
          if (t == 0) continue;  // unlabeled passes through with confidence 1
          if (group_of[t] != group) {
            group_of[t] = group;
            const double u = uniform01(rng);
            std::size_t p = 0;
            while (u >= cumulative_[t][p]) ++p;
            group_label[t] = static_cast<std::uint8_t>(p);
            group_conf[t] = draw_confidence(t, p == t);
          }
          out.labels.pixels[row + x] = group_label[t];
          out.confidence.pixels[row + x] = group_conf[t];
        }
      }
    }
  }

  // 2. Boundary erosion: near-edge pixels take the step-1 prediction of their nearest neighbour of
  // another labelled class.
  const int k = config_.boundary_width_px;
  if (k == 0 || config_.boundary_probability <= 0.0) return;
  const std::vector<std::uint8_t> step1 = out.labels.pixels;
  const auto& L = truth.pixels;
  // Near an edge iff the (2k+1)^2 window holds two different labelled classes: separable min/max
  // of the labelled ids (unlabeled ignored).
  const std::size_t n = L.size();
  std::vector<std::uint8_t> hmin(n), hmax(n);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) {
      std::uint8_t lo = 255, hi = 0;
      for (int xx = std::max(0, x - k); xx <= std::min(w - 1, x + k); ++xx) {
        const std::uint8_t v = L[row + xx];
        if (v == 0) continue;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
      }
      hmin[row + x] = lo;
      hmax[row + x] = hi;
    }
  }
  const double q = config_.boundary_probability;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      const std::uint8_t t = L[i];
      if (t == 0) continue;
      std::uint8_t lo = 255, hi = 0;
      for (int yy = std::max(0, y - k); yy <= std::min(h - 1, y + k); ++yy) {
        const std::size_t j = static_cast<std::size_t>(yy) * w + x;
        lo = std::min(lo, hmin[j]);
        hi = std::max(hi, hmax[j]);
      }
      if (lo == hi) continue;  // only this pixel's class around
      if (uniform01(rng) >= q) continue;
      // Nearest pixel of another labelled class.
      int best_d2 = std::numeric_limits<int>::max();
      std::size_t best = i;
      for (int yy = std::max(0, y - k); yy <= std::min(h - 1, y + k); ++yy) {
        for (int xx = std::max(0, x - k); xx <= std::min(w - 1, x + k); ++xx) {
          const std::size_t j = static_cast<std::size_t>(yy) * w + xx;
          const int d2 = (xx - x) * (xx - x) + (yy - y) * (yy - y);
          if (L[j] != 0 && L[j] != t && d2 < best_d2) {
            best_d2 = d2;
            best = j;
          }
        }
      }
      const std::uint8_t p = step1[best];
      out.labels.pixels[i] = p;
      out.confidence.pixels[i] = draw_confidence(t, p == t);
    }
  }
}

double LabelConfusionModel::confidence_density(SemanticClass true_class, bool correct, double c) const {
  const BetaParams& b = beta(idx(true_class), correct);
  if (!(c > 0.0 && c < 1.0)) return 0.0;
  return std::exp(b.log_norm + (b.a - 1.0) * std::log(c) + (b.b - 1.0) * std::log1p(-c));
}

double LabelConfusionModel::mean_confidence(SemanticClass true_class, bool correct) const {
  const BetaParams& b = beta(idx(true_class), correct);
  return b.a / (b.a + b.b);
}

ClassProbabilities LabelConfusionModel::posterior(SemanticClass predicted) const {
  const std::size_t p = idx(predicted);
  if (p >= K) throw std::invalid_argument("LabelConfusionModel::posterior: invalid class id " + std::to_string(p));
  ClassProbabilities post{};
  double sum = 0.0;
  for (std::size_t t = 0; t < K; ++t) sum += post[t] = prior_[t] * matrix_[t][p];
  if (!(sum > 0.0)) {
    post[p] = 1.0;
    return post;
  }
  for (double& v : post) v /= sum;
  return post;
}

ClassProbabilities LabelConfusionModel::posterior(SemanticClass predicted, double confidence) const {
  const std::size_t p = idx(predicted);
  if (p >= K) throw std::invalid_argument("LabelConfusionModel::posterior: invalid class id " + std::to_string(p));
  if (!(confidence >= 0.0 && confidence <= 1.0)) {
    throw std::invalid_argument("LabelConfusionModel::posterior: confidence must be in [0, 1], found " + str(confidence));
  }
  const double c = std::clamp(confidence, kPosteriorClamp, 1.0 - kPosteriorClamp);
  const double log_c = std::log(c), log_1mc = std::log1p(-c);
  // Log weights, normalized by their maximum: the Beta densities span many orders of magnitude.
  ClassProbabilities logw{};
  double max_logw = -std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < K; ++t) {
    const double m = prior_[t] * matrix_[t][p];
    if (!(m > 0.0)) {
      logw[t] = -std::numeric_limits<double>::infinity();
      continue;
    }
    const BetaParams& b = beta(t, t == p);
    logw[t] = std::log(m) + b.log_norm + (b.a - 1.0) * log_c + (b.b - 1.0) * log_1mc;
    max_logw = std::max(max_logw, logw[t]);
  }
  ClassProbabilities post{};
  if (max_logw == -std::numeric_limits<double>::infinity()) {
    post[p] = 1.0;
    return post;
  }
  double sum = 0.0;
  for (std::size_t t = 0; t < K; ++t) sum += post[t] = std::exp(logw[t] - max_logw);
  for (double& v : post) v /= sum;
  return post;
}

}  // namespace navaid::simulation
