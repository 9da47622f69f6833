// The line writers regmapgen's emitters share: the layouts clang-format keeps unchanged (Google style, 110
// columns). regmap.generated_format checks whole generated files; these pin each rule on its own.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "emit/lines.hpp"

namespace regmapgen {
namespace {

std::string longText(int words) {
  std::string s;
  for (int i = 0; i < words; ++i)
    s += (i ? " " : "") + std::string("word") + std::to_string(i);
  return s;
}

TEST(Lines, CommentsWrapAtTheColumnLimitAndKeepEveryWord) {
  std::ostringstream o;
  writeComment(o, longText(40), 2);
  std::istringstream in(o.str());
  std::string line, joined;
  int lines = 0;
  while (std::getline(in, line)) {
    ++lines;
    EXPECT_LE(line.size(), kColumnLimit) << line;
    ASSERT_EQ(line.rfind("  // ", 0), 0U) << line;
    joined += (joined.empty() ? "" : " ") + line.substr(5);
  }
  EXPECT_GT(lines, 1);
  EXPECT_EQ(joined, longText(40));
}

TEST(Lines, AWordLongerThanALineStaysWhole) {
  std::ostringstream o;
  const std::string word(130, 'x');
  writeComment(o, "a " + word + " b");
  EXPECT_EQ(o.str(), "// a\n// " + word + "\n// b\n");
}

TEST(Lines, BracedListsStayOnOneLineOnlyWhenTheyFit) {
  std::ostringstream shortList, longList;
  writeBraced(shortList, 0, "int a[] = ", {"1", "2"}, ";");
  EXPECT_EQ(shortList.str(), "int a[] = {1, 2};\n");
  writeBraced(longList, 2, "  int b[] = ", {std::string(60, 'x'), std::string(60, 'y')}, ";");
  EXPECT_EQ(longList.str(), "  int b[] = {\n      " + std::string(60, 'x') + ",\n      " +
                                std::string(60, 'y') + ",\n  };\n");
}

TEST(Lines, TrailingCommentsAlignOrMoveAboveTheirLine) {
  std::ostringstream aligned, above;
  writeCommented(aligned, {{"  A = 0,", "zero"}, {"  Longer = 1,", "one"}, {"  B = 2,", ""}});
  EXPECT_EQ(aligned.str(), "  A = 0,       // zero\n  Longer = 1,  // one\n  B = 2,\n");
  writeCommented(above, {{"  A = 0,", std::string(100, 'z')}, {"  B = 1,", "one"}});
  EXPECT_EQ(above.str(), "  // " + std::string(100, 'z') + "\n  A = 0,\n  // one\n  B = 1,\n");
}

TEST(Lines, DeclarationsBreakBeforeTheNameWhenTooLong) {
  std::ostringstream fits, breaks;
  writeDeclaration(fits, "inline constexpr T", "Name");
  EXPECT_EQ(fits.str(), "inline constexpr T Name{};\n");
  writeDeclaration(breaks, "inline constexpr " + std::string(90, 'T'), "LongName");
  EXPECT_EQ(breaks.str(), "inline constexpr " + std::string(90, 'T') + "\n    LongName{};\n");
}

}  // namespace
}  // namespace regmapgen
