// The benchmark's Markdown table: every row has the same number of columns, even where a
// header holds a '|' ("fan step max |err|"), and the width padding never goes negative.
#include <gtest/gtest.h>

#include <sstream>

#include "sim/bench.h"
#include "sim/plants.h"

namespace sim {
namespace {

std::size_t unescaped_bars(const std::string& line) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < line.size(); ++i)
    if (line[i] == '|' && (i == 0 || line[i - 1] != '\\')) ++n;
  return n;
}

TEST(BenchTable, MarkdownRowsHaveEqualColumnsWithADisturbance) {
  BenchCase c;
  c.config.plant = *find_plant("hotend40w");
  RunResult r;
  r.config = c.config;
  r.metrics.disturbance = DisturbanceMetrics{};  // adds the "max |err|" columns
  std::ostringstream out;
  print_bench_table(out, {c, c}, {r, r}, true, "fan step");
  std::istringstream lines(out.str());
  std::string line;
  std::size_t bars = 0, rows = 0;
  while (std::getline(lines, line)) {
    if (rows == 0) bars = unescaped_bars(line);
    EXPECT_EQ(unescaped_bars(line), bars) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 4u);  // header, separator, two runs
  EXPECT_NE(out.str().find("max \\|err\\|"), std::string::npos);
}

}  // namespace
}  // namespace sim
