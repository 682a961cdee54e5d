// The emergency parser (firmware/gcode_emergency_parser.h): which byte streams fire M112/M108,
// and that everything the line parser would run as M112/M108 fires it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "firmware/gcode_command.h"
#include "firmware/gcode_emergency_parser.h"

namespace {

using gcode::EmergencyParser;
using gcode::Urgent;

// Feeds `bytes`; returns what fired and after how many bytes, as "stop@4 cancel@12".
std::string fired(const std::string& bytes, EmergencyParser parser = EmergencyParser()) {
  std::string result;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const Urgent u = parser.feed(static_cast<uint8_t>(bytes[i]));
    if (u == Urgent::kNone) continue;
    if (!result.empty()) result += ' ';
    result += (u == Urgent::kStop ? "stop@" : "cancel@") + std::to_string(i + 1);
  }
  return result;
}

TEST(EmergencyParser, FiresWhenTheWordEnds) {
  EXPECT_EQ(fired("M112\n"), "stop@5");
  EXPECT_EQ(fired("M108\n"), "cancel@5");
  EXPECT_EQ(fired("M112 ; stop\n"), "stop@5");
  EXPECT_EQ(fired("M112*64\n"), "stop@5");
  EXPECT_EQ(fired("M112;x\n"), "stop@5");
  EXPECT_EQ(fired("M108S1\n"), "cancel@5");
  EXPECT_EQ(fired("M112\r"), "stop@5");
  EXPECT_EQ(fired("m112\n"), "stop@5");
  EXPECT_EQ(fired("M0112\n"), "stop@6");
  EXPECT_EQ(fired("M112\tS1\n"), "stop@5");
}

TEST(EmergencyParser, AfterALineNumberAndBlanks) {
  EXPECT_EQ(fired("N12 M112*47\n"), "stop@9");
  EXPECT_EQ(fired("  N7   M108\n"), "cancel@12");
  EXPECT_EQ(fired("N7M112\n"), "stop@7");
  EXPECT_EQ(fired("\tM112\n"), "stop@6");
}

TEST(EmergencyParser, IgnoresEverythingElse) {
  EXPECT_EQ(fired("M1120\n"), "");
  EXPECT_EQ(fired("M11\n"), "");
  EXPECT_EQ(fired("M1122\nM12\n"), "");
  EXPECT_EQ(fired("M104 S112\n"), "");
  EXPECT_EQ(fired("G1 M112\n"), "");
  EXPECT_EQ(fired("; M112\n"), "");
  EXPECT_EQ(fired("M112.5\n"), "");          // the line parser refuses it as well
  EXPECT_EQ(fired("M112-\n"), "");
  EXPECT_EQ(fired(std::string("M112") + '\x01' + "\n"), "");
  EXPECT_EQ(fired("M99999999999112\n"), "");  // saturates, never wraps to 112
  EXPECT_EQ(fired("M410\n"), "");             // left out: see the header
  EXPECT_EQ(fired("M"), "");
}

TEST(EmergencyParser, EveryLineStartsAfresh) {
  EXPECT_EQ(fired("M105\nM112\nG28 M112\nM108\n"), "stop@10 cancel@24");
  EXPECT_EQ(fired("M105 M112\r\nM112\n"), "stop@16");
}

TEST(EmergencyParser, LostBytesCountAsALineStart) {
  EmergencyParser parser;
  for (char c : std::string("M104 S2")) parser.feed(static_cast<uint8_t>(c));
  parser.lost();  // the newline and more may be gone: a stop right after must still fire
  EXPECT_EQ(fired("M112\n", parser), "stop@5");
}

// Any line the line parser runs as M112/M108 must have fired here first (the line path only
// answers "ok" for M108). Checks every command word the parser accepts over a small alphabet.
TEST(EmergencyParser, CoversWhatTheLineParserAccepts) {
  const std::string alphabet = "M0128 N;S\t";
  std::vector<std::string> lines{""};
  int checked = 0;
  for (int length = 1; length <= 6; ++length) {
    std::vector<std::string> next;
    for (const std::string& prefix : lines)
      for (char c : alphabet) next.push_back(prefix + c);
    for (const std::string& text : next) {
      // What the line layer hands the parser: tabs as blanks, comment cut, N<digits> skipped.
      std::string line = text.substr(0, text.find(';'));
      for (char& c : line) c = c == '\t' ? ' ' : c;
      std::size_t start = line.find_first_not_of(' ');
      if (start == std::string::npos) continue;
      line = line.substr(start);
      if (line[0] == 'N' || line[0] == 'n') {
        std::size_t i = 1;
        while (i < line.size() && line[i] >= '0' && line[i] <= '9') ++i;
        line = line.substr(i);
      }
      gcode::Command cmd;
      if (!cmd.parse(line.c_str()) || cmd.letter != 'M' || (cmd.code != 112 && cmd.code != 108)) continue;
      const std::string want = cmd.code == 112 ? "stop@" : "cancel@";
      ASSERT_EQ(fired(text + "\n").substr(0, want.size()), want) << '"' << text << '"';
      ++checked;
    }
    lines = std::move(next);
  }
  EXPECT_GT(checked, 100);  // the search did reach such lines
}

}  // namespace
