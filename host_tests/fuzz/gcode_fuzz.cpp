// libFuzzer target for the G-code layer: the real Interpreter, ControllerBank and
// ControllerCommands (host_tests/controller_rig.h) fed arbitrary bytes, line by line. Built with
// clang under ASan and UBSan (host_tests/fuzz/CMakeLists.txt); any sanitizer report is a crash.
// Protocol oracles, checked after every line:
//   - a line with a command character in it gets exactly one "ok"; one without gets none;
//   - a line answered with "Error:" (other than M112's stop and a resend request, which do not
//     touch the settings either) changes no setting: the bank's settings, the state-feedback
//     constants and M503's text are as before.
// After every line the controller in force runs a few control periods across the whole
// temperature range, so settings that overflow the control law show up as UBSan reports.
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "host_tests/controller_rig.h"

namespace {

// What the settings are now: everything M500 would store plus M503's text.
std::string settings_digest(controller_test::Rig& rig) {
  std::string digest;
  const firmware::Settings& s = rig.machine.bank.settings();
  digest.append(reinterpret_cast<const char*>(&s), sizeof s);
  const control::StateFeedbackConstants& k = rig.machine.bank.state_feedback_constants();
  digest.append(reinterpret_cast<const char*>(&k), sizeof k);
  digest += rig.machine.bank.state_feedback_loaded() ? '1' : '0';
  gcode_test::StringOutput report;
  rig.machine.commands.report(report);
  return digest + report.take();
}

size_t count_ok_lines(const std::string& out) {
  size_t n = 0;
  size_t start = 0;
  while (start < out.size()) {
    size_t end = out.find('\n', start);
    if (end == std::string::npos) end = out.size();
    if (out.compare(start, end - start, "ok") == 0 || out.compare(start, 3, "ok ") == 0) ++n;
    start = end + 1;
  }
  return n;
}

// A line the protocol answers: any byte but a blank before a ';' comment (a control character
// or NUL is answered with an Error, bytes above 0x7F as an unknown command).
bool has_command_text(const std::string& line) {
  for (char c : line) {
    if (c == ';') return false;
    if (c != ' ' && c != '\t') return true;
  }
  return false;
}

[[noreturn]] void fail(const char* what, const std::string& line, const std::string& out) {
  std::fprintf(stderr, "oracle: %s\nline: \"%s\"\nreply: \"%s\"\n", what, line.c_str(), out.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  controller_test::Rig rig;
  uint32_t now_ms = 0;
  std::string line;
  for (size_t i = 0; i <= size; ++i) {
    const bool end = i == size;
    const char c = end ? '\n' : static_cast<char>(data[i]);
    if (c != '\n' && c != '\r') {
      line += c;
      continue;
    }
    const std::string before = settings_digest(rig);
    for (char b : line) rig.gcode.feed(b);
    rig.gcode.feed('\n');
    now_ms += 128;
    rig.gcode.poll(now_ms);
    const std::string out = rig.out.take();
    const size_t oks = count_ok_lines(out);
    // The assembler bounds a line; one far longer than its buffer is still one line.
    if (has_command_text(line) ? oks != 1 : oks != 0) fail("not exactly one ok for the line", line, out);
    const bool refused = out.find("Error:") != std::string::npos && out.find("Emergency stop") == std::string::npos &&
                         out.find("Resend:") == std::string::npos;
    if (refused && settings_digest(rig) != before) fail("an Error: line changed the settings", line, out);
    if (out.find('\0') != std::string::npos) fail("NUL in the reply", line, out);
    if (!out.empty() && out.back() != '\n') fail("reply does not end its line", line, out);
    line.clear();
    // Whatever the settings are now, the control law must run: readings from 0 to 500 °C
    // against a 210 °C target with the fan on and off (int32 overflow is a UBSan report).
    for (int32_t t = 0; t <= 500; t += 125) {
      rig.machine.bank.step(control::StepInput{210L * 256, t * 256, static_cast<uint8_t>(t & 0x80 ? 255 : 0)});
    }
  }
  return 0;
}
