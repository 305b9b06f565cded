// Both fusion policies' rules, one vote at a time.
#include <gtest/gtest.h>

#include "navaid/mapping/semantic_fusion.hpp"

namespace navaid::mapping {
namespace {

using C = SemanticClass;

TEST(MaxFusion, FirstVoteSetsTheClass) {
  MaxFusion::State s;
  MaxFusion::fuse(s, {C::kCar, 0.8f}, {});
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kCar);
  EXPECT_FLOAT_EQ(MaxFusion::belief(s).probability, 0.8f);
}

TEST(MaxFusion, SameClassAveragesTheConfidences) {
  MaxFusion::State s;
  MaxFusion::fuse(s, {C::kPole, 0.9f}, {});
  MaxFusion::fuse(s, {C::kPole, 0.5f}, {});
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kPole);
  EXPECT_FLOAT_EQ(MaxFusion::belief(s).probability, 0.7f);
}

TEST(MaxFusion, DifferentClassKeepsTheMoreConfidentOneDiscounted) {
  MaxFusion::Params params;
  params.disagreement_discount = 0.9f;
  MaxFusion::State s;
  MaxFusion::fuse(s, {C::kPole, 0.6f}, params);
  MaxFusion::fuse(s, {C::kTreeTrunk, 0.4f}, params);  // weaker: pole kept, discounted
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kPole);
  EXPECT_FLOAT_EQ(MaxFusion::belief(s).probability, 0.54f);
  MaxFusion::fuse(s, {C::kTreeTrunk, 0.8f}, params);  // stronger: trunk wins, discounted
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kTreeTrunk);
  EXPECT_FLOAT_EQ(MaxFusion::belief(s).probability, 0.72f);
}

TEST(MaxFusion, UnlabeledPointsCarryNoVote) {
  MaxFusion::State s;
  MaxFusion::fuse(s, {C::kUnlabeled, 0.0f}, {});
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kUnlabeled);
  MaxFusion::fuse(s, {C::kBench, 0.7f}, {});
  MaxFusion::fuse(s, {C::kUnlabeled, 0.0f}, {});
  EXPECT_EQ(MaxFusion::belief(s).semantic, C::kBench);
  EXPECT_FLOAT_EQ(MaxFusion::belief(s).probability, 0.7f);
}

TEST(BayesianHistogramFusion, OneVoteGivesItsLikelihoodAsPosterior) {
  BayesianHistogramFusion::State s;
  EXPECT_EQ(BayesianHistogramFusion::belief(s).semantic, C::kUnlabeled);
  BayesianHistogramFusion::fuse(s, {C::kCar, 0.8f}, {});
  // Uniform prior over the 24 labelled classes: the posterior is the likelihood, normalised.
  EXPECT_EQ(BayesianHistogramFusion::belief(s).semantic, C::kCar);
  EXPECT_NEAR(BayesianHistogramFusion::belief(s).probability, 0.8, 1e-5);
}

TEST(BayesianHistogramFusion, TwoAgreeingVotesMultiply) {
  BayesianHistogramFusion::State s;
  BayesianHistogramFusion::fuse(s, {C::kCar, 0.6f}, {});
  BayesianHistogramFusion::fuse(s, {C::kCar, 0.6f}, {});
  const double others = static_cast<double>(kNumSemanticClasses) - 2.0;  // labelled classes but car
  const double other = 0.4 / others;
  const double expected = 0.36 / (0.36 + others * other * other);
  EXPECT_NEAR(BayesianHistogramFusion::belief(s).probability, expected, 1e-5);
}

TEST(BayesianHistogramFusion, MajorityWinsUnlikeMaxFusion) {
  // Three moderate "person" votes against one confident "pole": Bayes follows the evidence,
  // max fusion follows the single most confident vote.
  BayesianHistogramFusion::State b;
  MaxFusion::State m;
  for (const SemanticObservation obs : {SemanticObservation{C::kPole, 0.9f}, SemanticObservation{C::kPerson, 0.7f},
                                        SemanticObservation{C::kPerson, 0.7f}, SemanticObservation{C::kPerson, 0.7f}}) {
    BayesianHistogramFusion::fuse(b, obs, {});
    MaxFusion::fuse(m, obs, {});
  }
  EXPECT_EQ(BayesianHistogramFusion::belief(b).semantic, C::kPerson);
  EXPECT_EQ(MaxFusion::belief(m).semantic, C::kPole);
}

TEST(BayesianHistogramFusion, FloorLetsAClassComeBack) {
  BayesianHistogramFusion::Params params;
  BayesianHistogramFusion::State s;
  for (int i = 0; i < 200; ++i) BayesianHistogramFusion::fuse(s, {C::kCar, 0.95f}, params);
  for (float v : s.log_posterior) EXPECT_GE(v, params.log_floor);
  int votes_to_switch = 0;
  while (BayesianHistogramFusion::belief(s).semantic != C::kSidewalk && votes_to_switch < 100) {
    BayesianHistogramFusion::fuse(s, {C::kSidewalk, 0.95f}, params);
    ++votes_to_switch;
  }
  EXPECT_EQ(BayesianHistogramFusion::belief(s).semantic, C::kSidewalk);
  // Each vote gains ln(0.95 * 23 / 0.05) = 6.1 on the floor of -13.8: three votes.
  EXPECT_EQ(votes_to_switch, 3);
}

}  // namespace
}  // namespace navaid::mapping
