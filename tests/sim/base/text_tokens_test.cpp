#include "base/text_tokens.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "base/text_lines.hpp"

namespace cathbox::base::text {
namespace {

TEST(TextTokens, SplitsOnEveryBlankButNewline) {
  const auto t = split_tokens(" a\tb\r c\vd\fe  ");
  ASSERT_EQ(t.size(), 5u);
  EXPECT_EQ(t[0], "a");
  EXPECT_EQ(t[4], "e");
  EXPECT_TRUE(split_tokens(" \t ").empty());
}

TEST(TextTokens, NumbersWholeOrNothing) {
  EXPECT_EQ(parse_double("+2.5"), 2.5);
  EXPECT_FALSE(parse_double("2.5mm"));
  EXPECT_FALSE(parse_double(""));
  EXPECT_TRUE(parse_double("inf"));
  EXPECT_FALSE(parse_number("inf"));  // parse_number: finite only
  EXPECT_FALSE(parse_number("nan"));
  EXPECT_EQ(parse_integer("-7"), -7);
  EXPECT_FALSE(parse_integer("7.0"));
}

TEST(TextTokens, EscapeShowsOnlyPrintableAscii) {
  EXPECT_EQ(escape_bytes("a\nb"), "a\\x0ab");
  EXPECT_EQ(escape_bytes("\x7f\xc3\xa9"), "\\x7f\\xc3\\xa9");
  EXPECT_EQ(escape_bytes("abcdef", 3), "abc...");
  EXPECT_EQ(escape_bytes("abc", 3), "abc");
  EXPECT_EQ(text::quoted(std::string(50, 'x')), "'" + std::string(40, 'x') + "...'");  // not std::quoted
}

TEST(TextLines, SkipsCommentsAndBlankLinesAndCountsLines) {
  TextLines lines("# header\n\nkey 1 2 # note\r\n   \nlast");
  std::vector<std::string_view> words;
  ASSERT_TRUE(lines.next(words));
  EXPECT_EQ(lines.line(), 3u);
  ASSERT_EQ(words.size(), 3u);
  EXPECT_EQ(words[2], "2");
  ASSERT_TRUE(lines.next(words));
  EXPECT_EQ(lines.line(), 5u);
  EXPECT_EQ(words[0], "last");
  EXPECT_FALSE(lines.next(words));
  EXPECT_EQ(located("a.case", 3, "bad"), "a.case:3: bad");
}

}  // namespace
}  // namespace cathbox::base::text
