// Line assembly from the byte stream: terminators, comments, blanks, noise, overlong lines.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "firmware/gcode_line.h"

namespace {

using gcode::LineAssembler;

// Feeds `bytes` and returns the completed lines; "<overflow>" marks a discarded long line.
std::vector<std::string> lines_of(LineAssembler& assembler, const std::string& bytes) {
  std::vector<std::string> lines;
  for (char c : bytes) {
    const LineAssembler::Event event = assembler.feed(c);
    if (event == LineAssembler::Event::kLine) lines.push_back(assembler.text());
    if (event == LineAssembler::Event::kOverflow) lines.push_back("<overflow>");
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

TEST(GcodeLine, TabsBecomeBlanksAndControlBytesAreDropped) {
  LineAssembler a;
  EXPECT_EQ(lines_of(a, std::string("M104\tS2") + '\x01' + "00" + '\x7f' + "\n"),
            (std::vector<std::string>{"M104 S200"}));
  EXPECT_EQ(lines_of(a, std::string("M1") + '\0' + "05\n"), (std::vector<std::string>{"M105"}));
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
