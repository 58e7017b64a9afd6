#include "colmap_ext/util/string.h"

#include <gtest/gtest.h>

#include "colmap_ext/util/logging.h"

namespace colmap_lidar {
namespace {

TEST(String, Trim) {
  EXPECT_EQ(StringTrim("  a b \t\r\n"), "a b");
  EXPECT_EQ(StringTrim(" \t "), "");
  EXPECT_EQ(StringTrim("x"), "x");
}

TEST(String, SplitKeepsEmptyFields) {
  const std::vector<std::string> fields = StringSplit("a  b,c", " ,");
  ASSERT_EQ(fields.size(), 4u);
  EXPECT_EQ(fields[0], "a");
  EXPECT_EQ(fields[1], "");
  EXPECT_EQ(fields[2], "b");
  EXPECT_EQ(fields[3], "c");
  EXPECT_EQ(StringSplit("", " ").size(), 1u);
}

TEST(String, PrefixSuffixCase) {
  EXPECT_TRUE(StringStartsWith("--Section.name", "--"));
  EXPECT_FALSE(StringStartsWith("-", "--"));
  EXPECT_TRUE(StringEndsWith("scan.PLY", ".PLY"));
  EXPECT_FALSE(StringEndsWith("ply", ".ply"));
  EXPECT_EQ(StringToLower("PiNhOlE"), "pinhole");
  EXPECT_EQ(StringToUpper("pinhole"), "PINHOLE");
}

TEST(String, ParseNumbers) {
  EXPECT_DOUBLE_EQ(ParseDouble(" 1.5e3 ", "x"), 1500.0);
  EXPECT_EQ(ParseInt("-42", "x"), -42);
  try {
    ParseDouble("1.5abc", "option --a");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("option --a"), std::string::npos);
  }
  EXPECT_THROW(ParseDouble("", "x"), Error);
  EXPECT_THROW(ParseInt("4.5", "x"), Error);
  EXPECT_THROW(ParseInt("99999999999999999999999", "x"), Error);
}

}  // namespace
}  // namespace colmap_lidar
