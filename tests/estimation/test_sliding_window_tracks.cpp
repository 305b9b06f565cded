// FeatureTrackStore: the window's bookkeeping of tracks, anchors and parallax.
#include "navaid/estimation/feature_track_store.hpp"

#include <gtest/gtest.h>

#include "navaid/core/errors.hpp"
#include "test_support.hpp"

namespace navaid::estimation {
namespace {

std::pair<std::uint64_t, TrackObservation> obs(std::uint64_t id, double u, double v) {
  TrackObservation o;
  o.uv = Eigen::Vector2d(u, v);
  o.m = Eigen::Vector2d(u / 100.0, v / 100.0);
  return {id, o};
}

TEST(FeatureTrackStore, AnchorsAtFirstObservationAndReanchorsWhenItLeaves) {
  FeatureTrackStore store;
  store.add_frame(1, {obs(7, 10, 10), obs(8, 20, 20)});
  store.add_frame(2, {obs(7, 13, 14), obs(9, 5, 5)});
  store.add_frame(4, {obs(7, 16, 18), obs(9, 6, 5)});
  ASSERT_EQ(store.tracks().size(), 3u);
  EXPECT_EQ(store.tracks().at(7).observations.size(), 3u);
  EXPECT_EQ(store.anchored_at(1), (std::vector<std::uint64_t>{7, 8}));
  EXPECT_EQ(store.anchored_at(2), (std::vector<std::uint64_t>{9}));

  // Mean pixel displacement of the shared tracks: 7 moved 5 px (3-4-5), 9 did not exist in 1.
  int common = 0;
  EXPECT_DOUBLE_EQ(store.mean_parallax_px(1, 2, &common), 5.0);
  EXPECT_EQ(common, 1);
  EXPECT_DOUBLE_EQ(store.mean_parallax_px(2, 4, &common), 0.5 * (5.0 + 1.0));
  EXPECT_EQ(common, 2);
  EXPECT_DOUBLE_EQ(store.mean_parallax_px(1, 3, &common), 0.0);
  EXPECT_EQ(common, 0);

  store.remove_frame(1);
  EXPECT_EQ(store.tracks().count(8), 0u) << "a track without observations disappears";
  EXPECT_EQ(store.tracks().at(7).anchor().frame_id, 2u);
  EXPECT_EQ(store.anchored_at(2), (std::vector<std::uint64_t>{7, 9}));
  store.erase(9);
  EXPECT_EQ(store.tracks().size(), 1u);
}

TEST(FeatureTrackStore, FrameIdsMustIncrease) {
  FeatureTrackStore store;
  store.add_frame(3, {obs(1, 0, 0)});
  navaid::testing::expect_throw<Error>([&] { store.add_frame(3, {obs(1, 0, 0)}); }, "repeated frame id");
}

}  // namespace
}  // namespace navaid::estimation
