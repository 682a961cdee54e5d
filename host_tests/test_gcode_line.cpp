// Line assembly from the byte stream: terminators, comments, blanks, noise, overlong lines.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "firmware/gcode_line.h"

namespace {

using gcode::LineAssembler;

// Feeds `bytes` and returns the completed lines; "<overflow>" marks a discarded long line,
// "<control 0xNN>" one holding a control byte; "N" is appended when the discarded line was numbered.
std::vector<std::string> lines_of(LineAssembler& assembler, const std::string& bytes) {
  std::vector<std::string> lines;
  for (char c : bytes) {
    const LineAssembler::Event event = assembler.feed(c);
    const std::string n = assembler.numbered() ? " N" : "";
    if (event == LineAssembler::Event::kLine) lines.push_back(assembler.text());
    if (event == LineAssembler::Event::kOverflow) lines.push_back("<overflow>" + n);
    if (event == LineAssembler::Event::kControlChar) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "%02X", assembler.bad_byte());
      lines.push_back(std::string("<control 0x") + hex + ">" + n);
    }
  }
  return lines;
}

TEST(GcodeLine, CrLfAndCrlfEndLinesAndEmptyLinesVanish) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "M105\nM104 S1\rM106\r\n\n\r\nM107"),
            (std::vector<std::string>{"M105", "M104 S1", "M106"}));
  EXPECT_EQ(lines_of(a, "\n"), (std::vector<std::string>{"M107"}));  // held until terminated
}

TEST(GcodeLine, CommentsAndBlanksAreStripped) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "M104 S200 ; heat *12 up\n; only a comment\n   \n  \tM105  \t \n"),
            (std::vector<std::string>{"M104 S200", "M105"}));
}

TEST(GcodeLine, TabsBecomeBlanks) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "M104\tS200\t\n"), (std::vector<std::string>{"M104 S200"}));
}

// Issue 8: control bytes were dropped silently, so "M10<DEL>4 S2<SOH>10" became "M104 S210".
TEST(GcodeLine, ControlBytesDiscardTheLine) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, std::string("M10") + '\x7f' + "4 S2" + '\x01' + "10\nM105\n"),
            (std::vector<std::string>{"<control 0x7F>", "M105"}));
  EXPECT_EQ(lines_of(a, std::string("M1") + '\0' + "05\n"), (std::vector<std::string>{"<control 0x00>"}));
  EXPECT_EQ(lines_of(a, std::string(" \x02N5 M105*3\n")), (std::vector<std::string>{"<control 0x02> N"}));
  EXPECT_EQ(lines_of(a, std::string("M105 ; \x03 in a comment\n")), (std::vector<std::string>{"M105"}));
}

TEST(GcodeLine, OverflowTellsWhetherTheLineWasNumbered) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "n12 M117 " + std::string(100, 'x') + "\n"), (std::vector<std::string>{"<overflow> N"}));
  EXPECT_EQ(lines_of(a, "  M117 " + std::string(100, 'x') + "\n"), (std::vector<std::string>{"<overflow>"}));
}

TEST(GcodeLine, LostInputDiscardsToTheEndOfTheLine) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "N7 M1"), (std::vector<std::string>{}));
  EXPECT_TRUE(a.lose());
  EXPECT_TRUE(a.numbered());
  EXPECT_FALSE(a.lose());  // the same stretch: report once
  EXPECT_EQ(lines_of(a, "01 P34\nM105\n"), (std::vector<std::string>{"M105"}));
  EXPECT_TRUE(a.lose());   // a new stretch
  EXPECT_EQ(lines_of(a, "\nM106\n"), (std::vector<std::string>{"M106"}));
}

TEST(GcodeLine, LongestLineFitsOneMoreOverflows) {
  LineAssembler a;
  const std::string longest(LineAssembler::kCapacity - 1, 'X');
  EXPECT_EQ(lines_of(a, longest + "\n"), (std::vector<std::string>{longest}));
  EXPECT_EQ(lines_of(a, longest + "Y\n"), (std::vector<std::string>{"<overflow>"}));
  EXPECT_EQ(lines_of(a, longest + "YZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ"
                               "ZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZZ\nM105\n"),
            (std::vector<std::string>{"<overflow>", "M105"}));  // next line is clean
}

TEST(GcodeLine, LongCommentDoesNotOverflow) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, "M105 ;" + std::string(300, 'c') + "\n"), (std::vector<std::string>{"M105"}));
}

}  // namespace
