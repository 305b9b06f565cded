// enum_names: one name table gives an enum's to_string and its *_from_string.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "navaid/core/enum_names.hpp"

namespace navaid {
namespace {

enum class Colour { kRed, kGreen, kBlue };

constexpr NameTable<Colour, 3> kColourNames{{
    {Colour::kRed, "red"},
    {Colour::kGreen, "green"},
    {Colour::kBlue, "light-blue"},
}};

// Both directions work at compile time, so a table can be checked by static_assert.
static_assert(enum_name(kColourNames, Colour::kGreen) == "green");
static_assert(*enum_value(kColourNames, "light-blue") == Colour::kBlue);
static_assert(!enum_value(kColourNames, "purple"));

TEST(EnumNames, ValueToName) {
  EXPECT_EQ(enum_name(kColourNames, Colour::kRed), "red");
  EXPECT_EQ(enum_name(kColourNames, Colour::kGreen), "green");
  EXPECT_EQ(enum_name(kColourNames, Colour::kBlue), "light-blue");
}

TEST(EnumNames, NameToValue) {
  EXPECT_EQ(enum_value(kColourNames, "red"), Colour::kRed);
  EXPECT_EQ(enum_value(kColourNames, "green"), Colour::kGreen);
  EXPECT_EQ(enum_value(kColourNames, "light-blue"), Colour::kBlue);
}

TEST(EnumNames, UnknownNameIsNullopt) {
  EXPECT_EQ(enum_value(kColourNames, "purple"), std::nullopt);
  EXPECT_EQ(enum_value(kColourNames, ""), std::nullopt);
  // Exact match only: no case folding, no prefixes, no trimming.
  EXPECT_EQ(enum_value(kColourNames, "Red"), std::nullopt);
  EXPECT_EQ(enum_value(kColourNames, "light"), std::nullopt);
  EXPECT_EQ(enum_value(kColourNames, "red "), std::nullopt);
  // The fallback name is not a name of the table.
  EXPECT_EQ(enum_value(kColourNames, "unknown"), std::nullopt);
}

TEST(EnumNames, UnknownValueGivesTheFallback) {
  const auto out_of_range = static_cast<Colour>(7);
  EXPECT_EQ(enum_name(kColourNames, out_of_range), "unknown");
  EXPECT_EQ(enum_name(kColourNames, out_of_range, "?"), "?");
  // The fallback is only for values without an entry.
  EXPECT_EQ(enum_name(kColourNames, Colour::kRed, "?"), "red");
}

TEST(EnumNames, ValueMissingFromATableGivesTheFallback) {
  constexpr NameTable<Colour, 2> partial{{{Colour::kRed, "red"}, {Colour::kBlue, "light-blue"}}};
  EXPECT_EQ(enum_name(partial, Colour::kGreen), "unknown");
  EXPECT_EQ(enum_value(partial, "green"), std::nullopt);
}

TEST(EnumNames, RoundTripsEveryEntry) {
  for (const Colour c : {Colour::kRed, Colour::kGreen, Colour::kBlue}) {
    EXPECT_EQ(enum_value(kColourNames, enum_name(kColourNames, c)), c) << enum_name(kColourNames, c);
  }
}

TEST(EnumNames, NamesInTableOrder) {
  EXPECT_EQ(enum_names(kColourNames), (std::vector<std::string>{"red", "green", "light-blue"}));
}

}  // namespace
}  // namespace navaid
