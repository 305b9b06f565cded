#include "navaid/simulation/label_confusion_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::simulation {
namespace {

constexpr std::size_t K = kNumSemanticClasses;
using C = SemanticClass;
std::size_t id(C c) { return static_cast<std::size_t>(c); }

// Independent draws per pixel: one-pixel cells, no erosion.
LabelConfusionConfig independent() {
  LabelConfusionConfig c;
  c.cell_size_px = 1;
  c.boundary_probability = 0.0;
  return c;
}

// Every pixel an independent uniform class in 1..K-1 (cell = 1), or one per cell x cell block.
ImageU8 random_labels(int w, int h, std::uint32_t seed, int block = 1) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cls(1, static_cast<int>(K) - 1);
  ImageU8 img(w, h);
  for (int by = 0; by < h; by += block)
    for (int bx = 0; bx < w; bx += block) {
      const auto v = static_cast<std::uint8_t>(cls(rng));
      for (int y = by; y < std::min(by + block, h); ++y)
        for (int x = bx; x < std::min(bx + block, w); ++x) img.at(x, y) = v;
    }
  return img;
}

// Counts[t][p] of predicted p for true t over `frames` frames.
std::vector<std::vector<double>> confusion_counts(const LabelConfusionModel& m, const ImageU8& truth, int frames) {
  std::vector<std::vector<double>> n(K, std::vector<double>(K, 0.0));
  for (int f = 0; f < frames; ++f) {
    const auto out = m.apply(truth, 21, static_cast<std::uint64_t>(f));
    for (std::size_t i = 0; i < truth.pixels.size(); ++i) n[truth.pixels[i]][out.labels.pixels[i]] += 1.0;
  }
  return n;
}

// Empirical rows against the matrix; `cluster` is the largest number of pixels sharing one draw,
// which bounds the variance of a pixel-weighted proportion by cluster * M (1 - M) / n.
void expect_rows_match(const LabelConfusionModel& m, const std::vector<std::vector<double>>& counts, double cluster) {
  for (std::size_t t = 1; t < K; ++t) {
    double n = 0.0;
    for (double v : counts[t]) n += v;
    ASSERT_GT(n, 1000.0) << t;
    for (std::size_t p = 0; p < K; ++p) {
      const double expected = m.matrix()[t][p];
      const double sd = std::sqrt(cluster * expected * (1.0 - expected) / n);
      EXPECT_NEAR(counts[t][p] / n, expected, 4.5 * sd + 1e-12) << "true " << t << " predicted " << p;
    }
  }
}

TEST(LabelConfusionModel, DefaultMatrixRowsAreNormalizedAndPlausible) {
  const LabelConfusionModel m;
  const auto& M = m.matrix();
  const auto acc = default_label_accuracy();
  for (std::size_t t = 0; t < K; ++t) {
    double sum = 0.0;
    for (std::size_t p = 0; p < K; ++p) {
      EXPECT_GE(M[t][p], 0.0);
      sum += M[t][p];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12) << t;
    EXPECT_EQ(M[t][t], acc[t]) << t;
    if (t > 0) {
      EXPECT_EQ(M[t][0], 0.0) << "unlabeled is never predicted";
    }
  }
  EXPECT_EQ(M[0][0], 1.0);
  // Implausible confusions carry no mass.
  EXPECT_EQ(M[id(C::kFloor)][id(C::kCeiling)], 0.0);
  EXPECT_EQ(M[id(C::kCeiling)][id(C::kFloor)], 0.0);
  EXPECT_EQ(M[id(C::kSky)][id(C::kRoad)], 0.0);
  EXPECT_EQ(M[id(C::kPerson)][id(C::kSky)], 0.0);
  // Sidewalk errors: weights road 3, tactile 2, curb 2, crosswalk 1, terrain 1, floor 1 (sum 10).
  const double err = 1.0 - acc[id(C::kSidewalk)];
  EXPECT_NEAR(M[id(C::kSidewalk)][id(C::kRoad)], err * 3.0 / 10.0, 1e-15);
  EXPECT_NEAR(M[id(C::kSidewalk)][id(C::kTerrain)], err / 10.0, 1e-15);
  EXPECT_GT(M[id(C::kRoad)][id(C::kSidewalk)], 0.0);  // pairs work both ways
  // Thin classes are harder than the default.
  EXPECT_LT(acc[id(C::kPole)], 0.9);
  EXPECT_LT(acc[id(C::kTrafficSign)], 0.9);
  EXPECT_LT(acc[id(C::kTactilePaving)], 0.9);
  EXPECT_LT(acc[id(C::kCurb)], 0.9);
}

TEST(LabelConfusionModel, RowOverrideReplacesTheRow) {
  LabelConfusionConfig c;
  ConfusionRowOverride o{C::kPole, {}};
  o.predicted[id(C::kPole)] = 3.0;
  o.predicted[id(C::kPerson)] = 1.0;
  c.row_overrides.push_back(o);
  const LabelConfusionModel m(c);
  EXPECT_DOUBLE_EQ(m.accuracy(C::kPole), 0.75);
  EXPECT_DOUBLE_EQ(m.matrix()[id(C::kPole)][id(C::kPerson)], 0.25);
  EXPECT_EQ(m.matrix()[id(C::kPole)][id(C::kTrafficSign)], 0.0);
  // Other rows keep their defaults.
  EXPECT_EQ(m.accuracy(C::kSidewalk), default_label_accuracy()[id(C::kSidewalk)]);
}

TEST(LabelConfusionModel, EmpiricalConfusionOfIndependentPixelsMatchesMatrix) {
  const LabelConfusionModel m(independent());
  expect_rows_match(m, confusion_counts(m, random_labels(320, 240, 1), 3), 1.0);
}

TEST(LabelConfusionModel, EmpiricalConfusionOverBlobsMatchesMatrix) {
  LabelConfusionConfig c;
  c.cell_size_px = 8;
  c.boundary_probability = 0.0;
  const LabelConfusionModel m(c);
  // 8 x 8 blocks of one class against a randomly shifted 8 x 8 cell grid: at most 64 pixels share
  // a draw; 16 frames give > 1000 independent groups per class.
  expect_rows_match(m, confusion_counts(m, random_labels(320, 240, 2, 8), 16), 64.0);
}

TEST(LabelConfusionModel, AccuracyOneAndNoiseOffAreIdentity) {
  LabelConfusionConfig c;
  c.accuracy.fill(1.0);
  c.boundary_probability = 0.0;
  const ImageU8 truth = random_labels(160, 120, 3, 5);
  const auto out = LabelConfusionModel(c).apply(truth, 4, 0);
  EXPECT_EQ(out.labels, truth);
  for (float v : out.confidence.pixels) {
    EXPECT_GT(v, 0.99f);
    EXPECT_LE(v, 1.0f);
  }
  LabelConfusionConfig off;
  off.noise = false;
  const auto clean = LabelConfusionModel(off).apply(truth, 4, 0);
  EXPECT_EQ(clean.labels, truth);
  EXPECT_EQ(clean.confidence, ImageF32(160, 120, 1, 1.0f));
}

TEST(LabelConfusionModel, UnlabeledPixelsPassThrough) {
  ImageU8 truth = random_labels(64, 64, 5);
  for (int x = 0; x < 64; ++x) truth.at(x, 10) = 0;
  LabelConfusionConfig c;
  c.accuracy.fill(0.5);
  c.accuracy[0] = 1.0;
  c.boundary_width_px = 3;
  c.boundary_probability = 1.0;
  const auto out = LabelConfusionModel(c).apply(truth, 6, 0);
  for (std::size_t i = 0; i < truth.pixels.size(); ++i) {
    EXPECT_EQ(truth.pixels[i] == 0, out.labels.pixels[i] == 0) << i;
    if (truth.pixels[i] == 0) {
      EXPECT_EQ(out.confidence.pixels[i], 1.0f);
    }
  }
}

// Fraction of horizontally adjacent pixel pairs with equal predictions on a one-class image.
double adjacent_agreement(const LabelConfusionConfig& c) {
  const ImageU8 truth(320, 240, 1, static_cast<std::uint8_t>(C::kSidewalk));
  const auto out = LabelConfusionModel(c).apply(truth, 8, 0);
  std::size_t same = 0, pairs = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x + 1 < 320; ++x, ++pairs) same += out.labels.at(x, y) == out.labels.at(x + 1, y);
  return static_cast<double>(same) / static_cast<double>(pairs);
}

TEST(LabelConfusionModel, ErrorsAreSpatiallyCoherent) {
  LabelConfusionConfig c;
  c.accuracy[id(C::kSidewalk)] = 0.6;
  c.boundary_probability = 0.0;
  const LabelConfusionModel m(c);
  double independent_agreement = 0.0;  // sum_p M[t][p]^2
  for (double v : m.matrix()[id(C::kSidewalk)]) independent_agreement += v * v;
  ASSERT_LT(independent_agreement, 0.45);
  // 16 px cells: only pairs straddling a cell border (1/16) can disagree.
  EXPECT_GT(adjacent_agreement(c), 0.95);
  // One-pixel cells are the independent control: agreement ~ sum_p M^2 (76k pairs, sd ~ 0.002).
  c.cell_size_px = 1;
  EXPECT_NEAR(adjacent_agreement(c), independent_agreement, 0.015);
}

TEST(LabelConfusionModel, BoundaryErosionTakesTheNeighboursLabelNearEdgesOnly) {
  LabelConfusionConfig c;
  c.accuracy[id(C::kSidewalk)] = 1.0;  // step 1 exact: every change is erosion
  c.accuracy[id(C::kRoad)] = 1.0;
  c.boundary_width_px = 2;
  c.boundary_probability = 0.5;
  const int w = 200, h = 300;
  ImageU8 truth(w, h, 1, static_cast<std::uint8_t>(C::kSidewalk));
  for (int y = 0; y < h; ++y)
    for (int x = w / 2; x < w; ++x) truth.at(x, y) = static_cast<std::uint8_t>(C::kRoad);
  const LabelConfusionModel m(c);
  const auto out = m.apply(truth, 10, 0);
  std::size_t flipped = 0;
  double conf_flipped = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool near = x >= w / 2 - 2 && x <= w / 2 + 1;
      const auto t = truth.at(x, y), p = out.labels.at(x, y);
      if (p != t) {
        ASSERT_TRUE(near) << x << "," << y;
        EXPECT_EQ(p, static_cast<std::uint8_t>(x < w / 2 ? C::kRoad : C::kSidewalk));
        ++flipped;
        conf_flipped += out.confidence.at(x, y);
      }
    }
  const double n = 4.0 * h;
  EXPECT_NEAR(static_cast<double>(flipped), 0.5 * n, 4.5 * std::sqrt(n * 0.25));
  // Eroded pixels report the confidence of wrong predictions: Beta(alpha, beta + 1).
  const double mean = m.mean_confidence(C::kRoad, false);
  // Beta(4, 1) has sd 0.16: ~600 draws give a standard error of 0.007.
  EXPECT_NEAR(conf_flipped / static_cast<double>(flipped), mean, 0.035);
  EXPECT_LT(conf_flipped / static_cast<double>(flipped), m.mean_confidence(C::kRoad, true) - 0.1);
}

struct ConfidenceSample {
  float c;
  bool correct;
};

std::vector<ConfidenceSample> confidence_samples(const LabelConfusionModel& m, int frames) {
  std::vector<ConfidenceSample> s;
  const ImageU8 truth = random_labels(320, 240, 12);
  for (int f = 0; f < frames; ++f) {
    const auto out = m.apply(truth, 31, static_cast<std::uint64_t>(f));
    for (std::size_t i = 0; i < truth.pixels.size(); ++i)
      s.push_back({out.confidence.pixels[i], out.labels.pixels[i] == truth.pixels[i]});
  }
  return s;
}

TEST(LabelConfusionModel, ConfidenceOfCorrectPredictionsIsHigher) {
  LabelConfusionConfig c = independent();
  c.accuracy.fill(0.7);
  c.accuracy[0] = 1.0;
  c.confidence_concentration = 4.0;
  const LabelConfusionModel m(c);
  // alpha = 2.8, beta = 1.2: E[c | correct] = 3.8 / 5, E[c | wrong] = 2.8 / 5.
  EXPECT_NEAR(m.mean_confidence(C::kRoad, true), 0.76, 1e-12);
  EXPECT_NEAR(m.mean_confidence(C::kRoad, false), 0.56, 1e-12);
  double sum[2] = {0, 0}, n[2] = {0, 0};
  for (const auto& s : confidence_samples(m, 2)) {
    ASSERT_GT(s.c, 0.0f);
    ASSERT_LE(s.c, 1.0f);
    sum[s.correct] += s.c;
    n[s.correct] += 1;
  }
  // Beta standard deviations are < 0.25; standard errors < 0.25 / sqrt(n).
  EXPECT_NEAR(sum[1] / n[1], 0.76, 4.5 * 0.25 / std::sqrt(n[1]));
  EXPECT_NEAR(sum[0] / n[0], 0.56, 4.5 * 0.25 / std::sqrt(n[0]));
  EXPECT_NEAR(n[1] / (n[0] + n[1]), 0.7, 4.5 * std::sqrt(0.21 / (n[0] + n[1])));
}

TEST(LabelConfusionModel, ConfidenceIsCalibrated) {
  LabelConfusionConfig c = independent();
  c.accuracy.fill(0.6);
  c.accuracy[0] = 1.0;
  const LabelConfusionModel m(c);
  // P(correct | c) = c: in every confidence bin the fraction correct equals the mean confidence.
  constexpr int kBins = 10;
  double n[kBins] = {}, correct[kBins] = {}, conf[kBins] = {};
  for (const auto& s : confidence_samples(m, 2)) {
    const int b = std::min(kBins - 1, static_cast<int>(s.c * kBins));
    n[b] += 1;
    correct[b] += s.correct;
    conf[b] += s.c;
  }
  int tested = 0;
  for (int b = 0; b < kBins; ++b) {
    if (n[b] < 500) continue;
    ++tested;
    const double mean_c = conf[b] / n[b];
    EXPECT_NEAR(correct[b] / n[b], mean_c, 4.5 * std::sqrt(mean_c * (1.0 - mean_c) / n[b])) << "bin " << b;
  }
  EXPECT_GE(tested, 7);
}

TEST(LabelConfusionModel, PosteriorSumsToOneAndPeaksAtThePrediction) {
  const LabelConfusionModel defaults;
  LabelConfusionConfig high;
  high.accuracy.fill(0.95);
  high.accuracy[0] = 1.0;
  const LabelConfusionModel accurate(high);
  for (std::size_t p = 0; p < K; ++p) {
    const auto pc = static_cast<C>(p);
    const auto post = defaults.posterior(pc);
    double sum = 0.0;
    for (double v : post) sum += v;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_EQ(std::max_element(post.begin(), post.end()) - post.begin(), static_cast<long>(p)) << p;
    for (double c : {0.55, 0.7, 0.9, 0.99, 1.0}) {
      const auto pcf = accurate.posterior(pc, c);
      double s = 0.0;
      for (double v : pcf) s += v;
      EXPECT_NEAR(s, 1.0, 1e-12);
      EXPECT_EQ(std::max_element(pcf.begin(), pcf.end()) - pcf.begin(), static_cast<long>(p)) << p << " c " << c;
    }
  }
  // A confident prediction is more certain than a hesitant one.
  EXPECT_GT(accurate.posterior(C::kPole, 0.99)[id(C::kPole)], accurate.posterior(C::kPole, 0.6)[id(C::kPole)]);
  // Unlabeled is certain.
  EXPECT_EQ(defaults.posterior(C::kUnlabeled)[0], 1.0);
  EXPECT_EQ(defaults.posterior(C::kUnlabeled, 0.3)[0], 1.0);
  // Without confidence: Bayes on the matrix with the uniform prior.
  const auto& M = defaults.matrix();
  double col = 0.0;
  for (std::size_t t = 0; t < K; ++t) col += M[t][id(C::kRoad)];
  EXPECT_NEAR(defaults.posterior(C::kRoad)[id(C::kSidewalk)], M[id(C::kSidewalk)][id(C::kRoad)] / col, 1e-15);
}

TEST(LabelConfusionModel, PosteriorWithPriorFallsBackToThePredictionWithoutEvidence) {
  LabelConfusionConfig c;
  c.prior.fill(0.0);
  c.prior[id(C::kRoad)] = 1.0;
  const LabelConfusionModel m(c);
  EXPECT_NEAR(m.posterior(C::kSidewalk)[id(C::kRoad)], 1.0, 1e-15);  // only road is possible
  const auto none = m.posterior(C::kCeiling);  // no road is ever predicted ceiling
  EXPECT_EQ(none[id(C::kCeiling)], 1.0);
  EXPECT_EQ(m.posterior(C::kCeiling, 0.8)[id(C::kCeiling)], 1.0);
}

TEST(LabelConfusionModel, PosteriorMatchesTheEmpiricalTrueClassFrequencies) {
  LabelConfusionConfig c = independent();
  c.prior.fill(1.0);
  c.prior[0] = 0.0;  // the test image draws classes 1..K-1 uniformly
  const LabelConfusionModel m(c);
  const ImageU8 truth = random_labels(320, 240, 14);
  std::vector<std::vector<double>> observed(K, std::vector<double>(K, 0.0)), expected = observed, var = observed;
  for (int f = 0; f < 2; ++f) {
    const auto out = m.apply(truth, 41, static_cast<std::uint64_t>(f));
    for (std::size_t i = 0; i < truth.pixels.size(); ++i) {
      const std::size_t p = out.labels.pixels[i];
      observed[p][truth.pixels[i]] += 1.0;
      const auto post = m.posterior(static_cast<C>(p), out.confidence.pixels[i]);
      for (std::size_t t = 0; t < K; ++t) {
        expected[p][t] += post[t];
        var[p][t] += post[t] * (1.0 - post[t]);
      }
    }
  }
  // Counts of true classes among pixels predicted p are Poisson-binomial with these moments.
  for (std::size_t p = 1; p < K; ++p)
    for (std::size_t t = 1; t < K; ++t)
      EXPECT_NEAR(observed[p][t], expected[p][t], 4.5 * std::sqrt(var[p][t]) + 0.5) << "predicted " << p << " true " << t;
}

TEST(LabelConfusionModel, DeterministicPerSeedAndFrameInAnyOrder) {
  const LabelConfusionModel m;
  const ImageU8 truth = random_labels(96, 64, 15, 6);
  std::vector<LabelPrediction> forward, backward(3);
  for (std::uint64_t k = 0; k < 3; ++k) forward.push_back(m.apply(truth, 5, k));
  for (std::uint64_t k = 3; k-- > 0;) backward[k] = m.apply(truth, 5, k);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(forward[k].labels, backward[k].labels);
    EXPECT_EQ(forward[k].confidence, backward[k].confidence);
  }
  EXPECT_FALSE(forward[0].confidence == forward[1].confidence);
  EXPECT_FALSE(m.apply(truth, 6, 0).confidence == forward[0].confidence);
}

TEST(LabelConfusionModel, ReusedBuffersGiveTheSameFrames) {
  const LabelConfusionModel m;
  LabelPrediction out;
  m.apply(random_labels(64, 48, 16, 4), 2, 0, out);
  const ImageU8 small = random_labels(32, 24, 17, 4);
  m.apply(small, 2, 1, out);
  const LabelPrediction fresh = m.apply(small, 2, 1);
  EXPECT_EQ(out.labels, fresh.labels);
  EXPECT_EQ(out.confidence, fresh.confidence);
}

TEST(LabelConfusionModel, BadConfigNamesTheKey) {
  const std::vector<std::pair<std::string, std::function<void(LabelConfusionConfig&)>>> cases = {
      {"accuracy.pole", [](LabelConfusionConfig& c) { c.accuracy[id(C::kPole)] = 1.5; }},
      {"accuracy.road", [](LabelConfusionConfig& c) { c.accuracy[id(C::kRoad)] = 0.0; }},
      {"accuracy.unlabeled", [](LabelConfusionConfig& c) { c.accuracy[0] = 0.9; }},
      {"accuracy.sidewalk", [](LabelConfusionConfig& c) { c.confusions.clear(); }},  // error mass, no partner
      {"confusions[0]", [](LabelConfusionConfig& c) { c.confusions[0].b = c.confusions[0].a; }},
      {"confusions[1]", [](LabelConfusionConfig& c) { c.confusions[1].a = C::kUnlabeled; }},
      {"confusions[2].weight", [](LabelConfusionConfig& c) { c.confusions[2].weight = 0.0; }},
      {"confusions[3]", [](LabelConfusionConfig& c) { c.confusions[3] = {c.confusions[0].b, c.confusions[0].a, 1.0}; }},
      {"row_overrides[0].true_class",
       [](LabelConfusionConfig& c) { c.row_overrides.push_back({C::kUnlabeled, uniform_class_prior()}); }},
      {"row_overrides[0].unlabeled",
       [](LabelConfusionConfig& c) { c.row_overrides.push_back({C::kPole, uniform_class_prior()}); }},
      {"row_overrides[0]", [](LabelConfusionConfig& c) { c.row_overrides.push_back({C::kPole, {}}); }},
      {"row_overrides[0].pole",
       [](LabelConfusionConfig& c) {
         ConfusionRowOverride o{C::kPole, {}};
         o.predicted[id(C::kPerson)] = 1.0;
         c.row_overrides.push_back(o);
       }},
      {"prior.road", [](LabelConfusionConfig& c) { c.prior[id(C::kRoad)] = -0.1; }},
      {"prior", [](LabelConfusionConfig& c) { c.prior.fill(0.0); }},
      {"cell_size_px", [](LabelConfusionConfig& c) { c.cell_size_px = 0; }},
      {"boundary_width_px", [](LabelConfusionConfig& c) { c.boundary_width_px = 17; }},
      {"boundary_probability", [](LabelConfusionConfig& c) { c.boundary_probability = std::nan(""); }},
      {"confidence_concentration", [](LabelConfusionConfig& c) { c.confidence_concentration = 0.0; }},
  };
  for (const auto& [key, edit] : cases) {
    LabelConfusionConfig c;
    edit(c);
    const auto e = testing::expect_throw<ConfigError>([&] { LabelConfusionModel m(c); }, key);
    ASSERT_TRUE(e);
    EXPECT_EQ(e->key(), key);
    EXPECT_EQ(e->file(), "label_confusion");
  }
  ImageU8 bad(8, 8, 1, 1);
  bad.at(4, 5) = static_cast<std::uint8_t>(K);
  const std::string msg = testing::error_message<std::invalid_argument>([&] { LabelConfusionModel().apply(bad, 1, 0); });
  EXPECT_NE(msg.find("(4, 5)"), std::string::npos) << msg;
  testing::expect_throw<std::invalid_argument>([] { LabelConfusionModel().posterior(C::kRoad, 1.5); });
  testing::expect_throw<std::invalid_argument>([] { LabelConfusionModel().posterior(C::kRoad, std::nan("")); });
}

}  // namespace
}  // namespace navaid::simulation
