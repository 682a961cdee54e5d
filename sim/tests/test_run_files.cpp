// The trace CSV written by --csv is what `plot` reads back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

#include "sim/run_files.h"
#include "sim/svg_plot.h"

namespace sim {
namespace {

TEST(RunFiles, TraceCsvRoundTripsThroughThePlotReader) {
  std::vector<TraceSample> trace(3);
  for (int i = 0; i < 3; ++i) {
    trace[i].t_s = 0.1 * (i + 1);
    trace[i].true_c = 25.0 + i;
    trace[i].sensor_c = 25.5 + i;
    trace[i].reported_c = i ? 25.0 : std::numeric_limits<double>::quiet_NaN();  // no report yet
    trace[i].target_c = 210.0;
    trace[i].heater_duty = 0.25 * i;
  }
  const std::string path = ::testing::TempDir() + "trace.csv";
  write_trace_csv(path, trace);
  const PlotSeries s = read_trace_csv(path, "run");
  std::remove(path.c_str());
  ASSERT_EQ(s.time_s.size(), 3u);
  EXPECT_DOUBLE_EQ(s.time_s[2], 0.3);
  EXPECT_DOUBLE_EQ(s.true_c[1], 26.0);
  EXPECT_DOUBLE_EQ(s.target_c[0], 210.0);
  EXPECT_DOUBLE_EQ(s.heater_duty[2], 50.0);  // plotted in %
}

TEST(RunFiles, PlotReaderRejectsOtherFiles) {
  const std::string path = ::testing::TempDir() + "other.csv";
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fputs("a,b\n1,2\n", f);
  std::fclose(f);
  EXPECT_THROW(read_trace_csv(path, "x"), std::runtime_error);
  std::remove(path.c_str());
}

// --save-settings / --settings: the lines come back as written, blank lines skipped; a missing
// or empty file is an error, never an empty replay that would test the firmware's defaults.
TEST(RunFiles, SettingsRoundTripAndEmptyFilesAreRefused) {
  const std::string path = ::testing::TempDir() + "tuned.gcode";
  const std::vector<std::string> lines = {"M307 A456.16 C599.70 D151.324 F47.754", "M310 S1 F1",
                                          "M570 T2 U15 P120 S4", "M301 P1.10768 I0.00185 D0.00"};
  ASSERT_TRUE(write_lines(path, lines));
  EXPECT_EQ(read_lines(path), lines);
  std::FILE* f = std::fopen(path.c_str(), "w");  // CRLF line ends and a blank line read the same
  std::fputs("M310 S1 F1\r\n\r\nM301 P1 I0.01 D0\r\n", f);
  std::fclose(f);
  EXPECT_EQ(read_lines(path), (std::vector<std::string>{"M310 S1 F1", "M301 P1 I0.01 D0"}));
  ASSERT_TRUE(write_lines(path, {}));
  EXPECT_THROW(read_lines(path), std::runtime_error);
  std::remove(path.c_str());
  EXPECT_THROW(read_lines(path), std::runtime_error);
}

}  // namespace
}  // namespace sim
