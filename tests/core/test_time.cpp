#include <gtest/gtest.h>

#include "navaid/core/time.hpp"

using namespace navaid;

TEST(Time, ParsesDecimalSecondsExactly) {
  EXPECT_EQ(parse_seconds("1403715273.262142976"), 1403715273262142976LL);
  EXPECT_EQ(parse_seconds("1305031102.175304"), 1305031102175304000LL);
  EXPECT_EQ(parse_seconds("12"), 12'000'000'000LL);
  EXPECT_EQ(parse_seconds(".5"), 500'000'000LL);
  EXPECT_EQ(parse_seconds("-1.25"), -1'250'000'000LL);
  EXPECT_EQ(parse_seconds("0.0000000015"), 2);  // tenth digit rounds
}

TEST(Time, ParsesScientificNotationToTheNanosecond) {
  // The rpg trajectory files write stamps this way; 19 significant digits carry the nanoseconds.
  EXPECT_EQ(parse_seconds("1.403715524907143116e+09"), 1403715524907143116LL);
  EXPECT_EQ(parse_seconds("1e-9"), 1);
}

TEST(Time, RejectsGarbage) {
  for (const char* bad : {"", "abc", "1.2.3", "12s", "nan", "inf", "-", ".", "1e400", "1.5e", "--1", "1,5"})
    EXPECT_FALSE(parse_seconds(bad).has_value()) << bad;
  for (const char* bad : {"", "1.5", "99999999999999999999", "12a", "-"})
    EXPECT_FALSE(parse_nanoseconds(bad).has_value()) << bad;
  EXPECT_EQ(parse_nanoseconds("1403715273262142976"), 1403715273262142976LL);
}

TEST(Time, FormatRoundTrips) {
  for (Timestamp t : {0LL, 1LL, -1LL, 1403715273262142976LL, -1'250'000'000LL, 999'999'999LL}) {
    const std::string s = format_seconds(t);
    EXPECT_EQ(parse_seconds(s), t) << s;
  }
  EXPECT_EQ(format_seconds(1403715273262142976LL), "1403715273.262142976");
  EXPECT_EQ(format_seconds(-1), "-0.000000001");
}

TEST(Time, DoubleConversions) {
  EXPECT_EQ(seconds_to_ns(1.5), 1'500'000'000LL);
  EXPECT_DOUBLE_EQ(ns_to_seconds(2'500'000'000LL), 2.5);
}
