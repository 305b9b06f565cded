// csv_field: free text as one CSV field.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "navaid/core/csv_field.hpp"

namespace {

TEST(CsvField, PlainTextStaysAsWritten) { EXPECT_EQ(navaid::csv_field("Bear left."), "Bear left."); }

TEST(CsvField, CommasQuotesAndLineBreaksAreQuoted) {
  EXPECT_EQ(navaid::csv_field("Obstacle ahead, go left."), "\"Obstacle ahead, go left.\"");
  EXPECT_EQ(navaid::csv_field("say \"stop\""), "\"say \"\"stop\"\"\"");
  EXPECT_EQ(navaid::csv_field("two\nlines"), "\"two lines\"");
}

}  // namespace

namespace navaid {
namespace {

TEST(SplitCsvFields, TakesBackWhatCsvFieldWrote) {
  const std::vector<std::string> texts{"plain", "with, comma", "a \"quote\"", "", "both, \"of\" them"};
  std::string line;
  for (std::size_t i = 0; i < texts.size(); ++i) line += (i > 0 ? "," : "") + csv_field(texts[i]);
  const auto fields = split_csv_fields(line);
  ASSERT_TRUE(fields);
  EXPECT_EQ(*fields, texts);
  EXPECT_EQ(*split_csv_fields("a,,b"), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(*split_csv_fields(""), (std::vector<std::string>{""}));
  EXPECT_FALSE(split_csv_fields("a,\"open"));
}

}  // namespace
}  // namespace navaid
