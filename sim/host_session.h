// A printer host on the simulated UART, the way OctoPrint/Pronterface talk to Marlin: one
// command line at a time, the next only after `ok`. Collects every reply line with its time
// and parses temperature reports (M105 replies and M155 auto-reports).
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/avr_board.h"

namespace sim {

struct ReplyLine {
  double t_s;
  std::string text;
};

// `T:<temp> /<target> ... @:<power>` as Marlin prints it (power 0..255, absent = -1).
struct TempReport {
  double t_s = 0.0;
  double temp_c = 0.0;
  double target_c = 0.0;
  int power = -1;
};
std::optional<TempReport> parse_temp_report(const std::string& line);

class HostSession {
 public:
  // Seconds a command may wait for its `ok` before the host gives up on it (and records it);
  // M109/M190 (set and wait) answer only when the temperature is reached, so they never time out.
  static constexpr double kOkTimeoutS = 5.0;

  explicit HostSession(AvrBoard& board);

  // Appends a command line (without newline) to the send queue; `on_ok` runs when its `ok`
  // arrives, with the simulated time; `on_sent` when its last byte went to the UART.
  void send(std::string line, std::function<void(double)> on_ok = {}, std::function<void(double)> on_sent = {});
  // Sends a line without waiting for the `ok`s before it, as hosts send M112/M108, or as a host
  // streaming ahead of its oks does: right after the line being sent (never inside it). Its
  // `ok` is matched to it (oks come in line order) and otherwise ignored.
  void send_now(std::string line, std::function<void(double)> on_sent = {});
  // Sends what may be sent now; call often (the harness does it every plant step).
  void poll();
  // True when every queued command has been answered (or timed out).
  bool idle() const { return queue_.empty() && !in_flight_ && urgent_.empty(); }

  int boot_count() const { return boot_count_; }  // `start` lines seen
  const std::vector<ReplyLine>& lines() const { return lines_; }
  // Every line both ways, in order: sent lines prefixed "> ", received ones "< ".
  const std::vector<ReplyLine>& transcript() const { return transcript_; }
  const std::vector<TempReport>& reports() const { return reports_; }
  const std::vector<std::string>& problems() const { return problems_; }
  // Called with each complete reply line as it arrives.
  void on_line(std::function<void(const ReplyLine&)> handler) { line_handler_ = std::move(handler); }

 private:
  void on_byte(uint8_t byte);
  void on_complete_line(std::string text);
  bool send_bytes(const std::string& text, std::size_t& sent);  // true once all are out

  AvrBoard& board_;
  struct Command {
    std::string text;  // with its newline
    std::function<void(double)> on_ok;
    std::function<void(double)> on_sent;
  };
  std::deque<Command> queue_;
  std::optional<Command> in_flight_;  // sent (or being sent), awaiting `ok`
  std::size_t bytes_sent_ = 0;        // of *in_flight_ (with its newline)
  std::deque<Command> urgent_;        // send_now() lines not yet fully sent
  std::size_t urgent_bytes_sent_ = 0;  // of urgent_.front()
  // Lines fully sent and awaiting their `ok`, in order: true = the in-flight command.
  std::deque<bool> awaiting_ok_;
  double in_flight_since_s_ = 0.0;
  std::string partial_;
  int boot_count_ = 0;
  std::vector<ReplyLine> lines_;
  std::vector<ReplyLine> transcript_;
  std::vector<TempReport> reports_;
  std::vector<std::string> problems_;
  std::function<void(const ReplyLine&)> line_handler_;
};

}  // namespace sim
