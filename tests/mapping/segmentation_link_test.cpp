// eLabrador §III.C: the edge's view of the cloud segmentation server over a simulated network,
// down detected at the first probe inside an outage, restored at the first probe after it.
#include <gtest/gtest.h>

#include <string>

#include "navaid/core/errors.hpp"
#include "navaid/mapping/segmentation_link.hpp"
#include "test_support.hpp"

namespace navaid::mapping {
namespace {

constexpr Timestamp kStart = 1'000'000'000'000;  // an arbitrary recording epoch
Timestamp at(double s) { return kStart + seconds_to_ns(s); }

SegmentationLinkConfig config(std::vector<NetworkOutage> outages, double period = 1.0, double timeout = 0.5) {
  SegmentationLinkConfig c;
  c.outages = std::move(outages);
  c.check_period_s = period;
  c.timeout_s = timeout;
  return c;
}

TEST(SegmentationLink, LossIsDetectedAtTheFirstProbeInsideTheOutagePlusTheTimeout) {
  // Outage [1.3, 3.2): probes at 0, 1, 2, 3, 4 s; the 2 s probe gets no reply, lost at 2.5 s; the
  // 3 s probe is still inside; the 4 s probe restores.
  SegmentationLink link(config({{1.3, 3.2}}), kStart);
  ASSERT_EQ(link.schedule().size(), 2u);
  EXPECT_EQ(link.schedule()[0], (NetworkChange{at(2.5), NetworkChangeKind::kLost}));
  EXPECT_EQ(link.schedule()[1], (NetworkChange{at(4.0), NetworkChangeKind::kRestored}));

  EXPECT_TRUE(link.labels_available(at(1.29)));
  EXPECT_FALSE(link.labels_available(at(1.3)));  // network down: nothing arrives, not yet declared
  EXPECT_TRUE(link.link_up(at(2.49)));
  EXPECT_FALSE(link.link_up(at(2.5)));
  EXPECT_FALSE(link.labels_available(at(3.5)));  // network back, the edge waits for its probe
  EXPECT_TRUE(link.network_up(at(3.5)));
  EXPECT_TRUE(link.labels_available(at(4.0)));
  EXPECT_EQ(link.outages_detected(), 1u);
}

TEST(SegmentationLink, ChangesAreRecordedAsTimePassesAndHandedOutOnce) {
  SegmentationLink link(config({{1.0, 2.0}, {5.5, 7.0}}), kStart);
  EXPECT_TRUE(link.labels_available(at(0.9)));
  EXPECT_TRUE(link.changes().empty());
  EXPECT_FALSE(link.labels_available(at(1.6)));  // probe at 1 s, lost at 1.5 s
  auto first = link.take_changes();
  ASSERT_EQ(first.size(), 1u);
  EXPECT_EQ(first[0], (NetworkChange{at(1.5), NetworkChangeKind::kLost}));
  EXPECT_TRUE(link.take_changes().empty());  // announced once
  EXPECT_TRUE(link.labels_available(at(2.0)));  // the 2 s probe: the outage ended exactly then
  EXPECT_FALSE(link.labels_available(at(6.7)));  // second outage: probe at 6 s, lost at 6.5 s
  EXPECT_TRUE(link.labels_available(at(8.0)));   // the 7 s probe restored it
  const auto rest = link.take_changes();
  ASSERT_EQ(rest.size(), 3u);
  EXPECT_EQ(rest[0], (NetworkChange{at(2.0), NetworkChangeKind::kRestored}));
  EXPECT_EQ(rest[1], (NetworkChange{at(6.5), NetworkChangeKind::kLost}));
  EXPECT_EQ(rest[2], (NetworkChange{at(7.0), NetworkChangeKind::kRestored}));
  EXPECT_EQ(link.changes().size(), 4u);
  EXPECT_EQ(link.outages_detected(), 2u);
  // An earlier query does not take back what was observed.
  EXPECT_TRUE(link.labels_available(at(0.0)));
  EXPECT_EQ(link.changes().size(), 4u);
}

TEST(SegmentationLink, AnOutageBetweenProbesLosesLabelsWithoutAStateChange) {
  SegmentationLink link(config({{1.2, 1.8}}), kStart);
  EXPECT_TRUE(link.schedule().empty());
  EXPECT_FALSE(link.labels_available(at(1.5)));
  EXPECT_TRUE(link.labels_available(at(1.8)));
  EXPECT_EQ(link.outages_detected(), 0u);
}

TEST(SegmentationLink, ARecoveryProbeInsideTheNextOutageKeepsTheLinkDown) {
  // Outages [1.0, 2.5) and [2.8, 3.4): the 3 s probe falls inside the second one, so the link comes
  // back only at 4 s, one loss for both.
  SegmentationLink link(config({{1.0, 2.5}, {2.8, 3.4}}), kStart);
  ASSERT_EQ(link.schedule().size(), 2u);
  EXPECT_EQ(link.schedule()[0].t, at(1.5));
  EXPECT_EQ(link.schedule()[1], (NetworkChange{at(4.0), NetworkChangeKind::kRestored}));
  EXPECT_FALSE(link.labels_available(at(2.6)));  // network up, link still down
}

TEST(SegmentationLink, TheProbePeriodSetsTheDetectionDelay) {
  SegmentationLink fast(config({{1.05, 2.0}}, 0.1, 0.05), kStart);
  ASSERT_EQ(fast.schedule().size(), 2u);
  EXPECT_EQ(fast.schedule()[0].t, at(1.15));  // probe at 1.1 s + 0.05 s
  EXPECT_EQ(fast.schedule()[1].t, at(2.0));
}

TEST(SegmentationLink, TheSameScheduleGivesTheSameChangesBitForBit) {
  const auto c = config({{0.37, 1.91}, {4.25, 4.26}, {6.0, 9.99}}, 0.3, 0.11);
  SegmentationLink a(c, kStart), b(c, kStart);
  EXPECT_EQ(a.schedule(), b.schedule());
  for (Timestamp t = kStart; t < at(12.0); t += 33'333'333) EXPECT_EQ(a.labels_available(t), b.labels_available(t));
  EXPECT_EQ(a.changes(), b.changes());
  EXPECT_EQ(a.outages_detected(), 2u);  // the 10 ms outage holds no probe
}

TEST(SegmentationLink, WithoutOutagesEveryFrameHasLabels) {
  SegmentationLink link(config({}), kStart);
  for (double s : {-1.0, 0.0, 0.5, 100.0}) EXPECT_TRUE(link.labels_available(at(s)));
  EXPECT_TRUE(link.changes().empty());
}

TEST(SegmentationLinkConfig, AbsentOutagesLeaveTheLinkOff) {
  EXPECT_FALSE(read_segmentation_link_config(Config::parse("{}")));
  const auto c = read_segmentation_link_config(Config::parse("{}", "<t>", {"mapping.network.outages=[1.0,2.0,5,6.5]"}));
  ASSERT_TRUE(c);
  ASSERT_EQ(c->outages.size(), 2u);
  EXPECT_DOUBLE_EQ(c->outages[1].start_s, 5.0);
  EXPECT_DOUBLE_EQ(c->outages[1].end_s, 6.5);
  EXPECT_DOUBLE_EQ(c->check_period_s, 1.0);
  EXPECT_DOUBLE_EQ(c->timeout_s, 0.5);
}

void expect_config_error(const std::string& assignment, const std::string& key, const std::string& words,
                         const std::string& more = "mapping.network.check_period_s=1") {
  const auto e = navaid::testing::expect_throw<ConfigError>(
      [&] { (void)read_segmentation_link_config(Config::parse("{}", "<t>", {assignment, more})); }, assignment);
  if (!e) return;
  EXPECT_EQ(e->key(), key) << e->what();
  EXPECT_NE(std::string(e->what()).find(words), std::string::npos) << e->what();
}

TEST(SegmentationLinkConfig, BadSchedulesNameTheKey) {
  expect_config_error("mapping.network.outages=[2.0,1.0]", "mapping.network.outages[0]", "ends before it starts");
  expect_config_error("mapping.network.outages=[1.0,1.0]", "mapping.network.outages[0]", "ends before it starts");
  expect_config_error("mapping.network.outages=[1,3,2,4]", "mapping.network.outages[1]", "overlaps");
  expect_config_error("mapping.network.outages=[5,6,1,2]", "mapping.network.outages[1]", "time order");
  expect_config_error("mapping.network.outages=[1,2,3]", "mapping.network.outages", "odd number");
  expect_config_error("mapping.network.outages=[[1,2]]", "mapping.network.outages", "start_s, end_s pairs");
  expect_config_error("mapping.network.outages=[-1,2]", "mapping.network.outages", "start_s, end_s pairs");
  expect_config_error("mapping.network.outages=off", "mapping.network.outages", "start_s, end_s pairs");
  expect_config_error("mapping.network.outages=[1,2]", "mapping.network.timeout_s", "shorter than",
                      "mapping.network.timeout_s=1.5");
  expect_config_error("mapping.network.outages=[1,2]", "mapping.network.check_period_s", "[0.01, 3600]",
                      "mapping.network.check_period_s=0");
}

TEST(SegmentationLinkConfig, TheConstructorChecksTooAndChangeNamesAreStable) {
  EXPECT_THROW(SegmentationLink(config({{3.0, 2.0}}), kStart), ConfigError);
  EXPECT_THROW(SegmentationLink(config({{1.0, 2.0}}, 1.0, 1.0), kStart), ConfigError);
  EXPECT_STREQ(network_change_name(NetworkChangeKind::kLost), "lost");
  EXPECT_STREQ(network_change_name(NetworkChangeKind::kRestored), "restored");
}

}  // namespace
}  // namespace navaid::mapping
