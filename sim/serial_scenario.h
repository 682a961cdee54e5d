// Host behaviours that stress the firmware's serial layer (issue 8), started at the fault time
// of a run (--fault KIND@SECONDS):
//   m112-wait         M109 above the target waits, one more line is held behind it, then (2 s
//                     later) M112 without waiting for ok: the heater must be off within 1 s.
//   m112-burst        the same M109, then a burst of lines sent without waiting for oks that
//                     fills the 128-byte RX ring, then M112 (its bytes are dropped by the full
//                     ring: only the emergency parser sees them).
//   overrun           the M109, a burst that overruns the ring (unnumbered lines), then M108
//                     (again seen only by the emergency parser) ends the wait.
//   overrun-numbered  the same with numbered, checksummed lines: the firmware must ask for the
//                     first lost line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/fault_outcome.h"
#include "sim/host_session.h"

namespace sim {

bool is_serial_scenario(FaultKind kind);

class SerialScenario {
 public:
  static constexpr int kBurstLines = 16;  // ~40 bytes each: 5 x the RX ring
  static constexpr double kHoldS = 2.0;   // M109 waiting before M112/M108 is sent

  SerialScenario(HostSession& session, FaultKind kind) : session_(session), kind_(kind) {}
  void start(double target_c);  // at the fault time
  void poll(double now_s);      // every plant step
  // When the last byte of the M112 (m112-*) or M108 (overrun*) went to the UART.
  std::optional<double> urgent_sent_s() const { return urgent_sent_s_; }

 private:
  void send_burst();
  void send_urgent();

  HostSession& session_;
  FaultKind kind_;
  std::optional<double> wait_sent_s_;  // the M109's last byte
  bool urgent_queued_ = false;
  std::optional<double> urgent_sent_s_;
};

// "N<n> <command>*<checksum>" as hosts send it.
std::string numbered_line(int n, const std::string& command);

// What the replies after `from_s` must show for the overrun kinds: an Error that says input was
// lost (with `Resend:` for the first lost line when numbered: every line before it answered once,
// none after it), and no line glued from pieces (no unknown command, no checksum or line-number
// error). Returns the problems found, empty when all is well.
std::vector<std::string> check_overrun_replies(FaultKind kind, const std::vector<ReplyLine>& lines, double from_s);

}  // namespace sim
