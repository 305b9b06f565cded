// csv_field: free text as one CSV field.
#include <gtest/gtest.h>

#include "navaid/core/csv_field.hpp"

namespace {

TEST(CsvField, PlainTextStaysAsWritten) { EXPECT_EQ(navaid::csv_field("Bear left."), "Bear left."); }

TEST(CsvField, CommasQuotesAndLineBreaksAreQuoted) {
  EXPECT_EQ(navaid::csv_field("Obstacle ahead, go left."), "\"Obstacle ahead, go left.\"");
  EXPECT_EQ(navaid::csv_field("say \"stop\""), "\"say \"\"stop\"\"\"");
  EXPECT_EQ(navaid::csv_field("two\nlines"), "\"two lines\"");
}

}  // namespace
