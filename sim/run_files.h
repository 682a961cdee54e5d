// Writes a run's records to files: the trace as CSV for plotting (one row per heater PWM
// period, 128 ms) and the serial transcript as text.
#pragma once

#include <string>
#include <vector>

#include "sim/host_session.h"
#include "sim/metrics.h"

namespace sim {

// Columns: time_s,true_c,sensor_c,reported_c,target_c,heater_duty,fan_duty (NaN → empty).
// Throws std::runtime_error if the file cannot be written.
void write_trace_csv(const std::string& path, const std::vector<TraceSample>& trace);
// One line per transcript entry: "<seconds> <line>".
void write_transcript(const std::string& path, const std::vector<ReplyLine>& transcript);
// Settings files (hotend-sim run --save-settings / --settings): one G-code line per text line.
// write_lines: false if the file cannot be written. read_lines: the non-empty lines; throws
// std::runtime_error if the file cannot be read or holds none.
bool write_lines(const std::string& path, const std::vector<std::string>& lines);
std::vector<std::string> read_lines(const std::string& path);

}  // namespace sim
