#include "navaid/simulation/time_grid.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace navaid::simulation {
namespace {

TEST(TimeGrid, IncludesBothEndsOnTheGridAndDoesNotDrift) {
  const auto t = time_grid(-1.0, 2.0, 30.0);
  ASSERT_EQ(t.size(), 91u);  // 3 s at 30 Hz, both ends
  EXPECT_EQ(t.front(), -1'000'000'000);
  EXPECT_EQ(t.back(), 2'000'000'000);
  for (std::size_t k = 0; k < t.size(); ++k) {  // each stamp within 0.5 ns of the exact time
    const double exact = -1e9 + static_cast<double>(k) * 1e9 / 30.0;
    EXPECT_LE(std::abs(static_cast<double>(t[k]) - exact), 0.5) << k;
  }
  EXPECT_EQ(time_grid(0.0, 0.0, 200.0).size(), 1u);
  EXPECT_EQ(time_grid(0.0, 0.0049, 200.0).size(), 1u);
  EXPECT_EQ(time_grid(0.0, 0.005, 200.0).size(), 2u);
}

TEST(TimeGrid, EmptyWhenReversedAndRejectsBadRates) {
  EXPECT_TRUE(time_grid(1.0, 0.0, 10.0).empty());
  EXPECT_THROW(time_grid(0.0, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(time_grid(0.0, 1.0, -5.0), std::invalid_argument);
}

}  // namespace
}  // namespace navaid::simulation
