#include "sim/serial_scenario.h"

#include <cstdlib>

namespace sim {

std::string numbered_line(int n, const std::string& command) {
  const std::string line = "N" + std::to_string(n) + " " + command;
  unsigned checksum = 0;
  for (char c : line) checksum ^= static_cast<unsigned char>(c);
  return line + "*" + std::to_string(checksum);
}

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

bool numbered_kind(FaultKind kind) { return kind == FaultKind::kOverrunNumbered; }

// A line of a burst: M105 (harmless, and its reply shows it ran) padded by a comment to ~40
// bytes, so 16 of them are 5 times the RX ring. The comment follows the checksum, if any.
std::string burst_line(int i, bool numbered) {
  const std::string padding = " ; burst line " + std::to_string(i) + " ..............";
  return (numbered ? numbered_line(i + 2, "M105") : "M105") + padding;
}

}  // namespace

bool is_serial_scenario(FaultKind kind) {
  return kind == FaultKind::kM112Wait || kind == FaultKind::kM112Burst || kind == FaultKind::kOverrun ||
         kind == FaultKind::kOverrunNumbered;
}

void SerialScenario::start(double target_c) {
  // 15 °C above the target: the wait lasts well beyond kHoldS on every plant.
  const std::string wait = "M109 S" + std::to_string(static_cast<int>(target_c) + 15);
  auto on_sent = [this](double t) {
    wait_sent_s_ = t;
    if (kind_ == FaultKind::kM112Wait) session_.send_now("M105");  // held behind the wait
    if (kind_ != FaultKind::kM112Wait) send_burst();
    if (kind_ == FaultKind::kM112Burst) send_urgent();  // right behind the burst
  };
  if (numbered_kind(kind_)) {
    session_.send(numbered_line(0, "M110 N0"));
    session_.send(numbered_line(1, wait), {}, on_sent);
  } else {
    session_.send(wait, {}, on_sent);
  }
}

void SerialScenario::send_burst() {
  for (int i = 0; i < kBurstLines; ++i)
    session_.send_now(burst_line(i, numbered_kind(kind_)));
}

void SerialScenario::send_urgent() {
  urgent_queued_ = true;
  const bool stop = kind_ == FaultKind::kM112Wait || kind_ == FaultKind::kM112Burst;
  session_.send_now(stop ? "M112" : "M108", [this](double t) { urgent_sent_s_ = t; });
}

void SerialScenario::poll(double now_s) {
  if (wait_sent_s_ && !urgent_queued_ && now_s >= *wait_sent_s_ + kHoldS) send_urgent();
}

std::vector<std::string> check_overrun_replies(FaultKind kind, const std::vector<ReplyLine>& lines, double from_s) {
  std::vector<std::string> problems;
  bool lost_reported = false;
  int answered_before = 0;  // "ok T:" replies to burst lines before the loss report
  std::optional<int> resend;
  for (const ReplyLine& line : lines) {
    if (line.t_s < from_s) continue;
    const std::string& text = line.text;
    if (starts_with(text, "ok T:") && !lost_reported) ++answered_before;
    if (starts_with(text, "ok T:") && lost_reported) problems.push_back("a line after the lost input ran: " + text);
    if (starts_with(text, "Error:") && text.find("serial input lost") != std::string::npos) {
      if (lost_reported && numbered_kind(kind)) problems.push_back("input loss reported twice: " + text);
      lost_reported = true;
      continue;
    }
    if (starts_with(text, "Resend:")) resend = std::atoi(text.c_str() + 7);
    if (starts_with(text, "Error:") || starts_with(text, "echo:Unknown command"))
      problems.push_back("a damaged line reached the parser: " + text);
  }
  if (!lost_reported) problems.push_back("no `Error:` saying serial input was lost");
  if (numbered_kind(kind)) {
    // Lines N2.. were the burst: the ones answered are N2..N(1 + answered); the next is the first lost.
    const int first_lost = 2 + answered_before;
    if (!resend) problems.push_back("no `Resend:` after the lost input");
    if (resend && *resend != first_lost)
      problems.push_back("Resend: " + std::to_string(*resend) + ", but the first lost line is N" +
                         std::to_string(first_lost));
  }
  if (answered_before >= SerialScenario::kBurstLines) problems.push_back("nothing was lost: the burst did not overrun");
  return problems;
}

}  // namespace sim
