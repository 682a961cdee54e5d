#include "sim/host_session.h"

#include <cstdio>
#include <cstdlib>

namespace sim {
namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

bool waits_for_temperature(const std::string& command) {
  return starts_with(command, "M109") || starts_with(command, "M190");
}

// Position of a `key` that starts a token (line start or after a space), or npos.
std::size_t find_token(const std::string& line, const std::string& key) {
  for (std::size_t pos = line.find(key); pos != std::string::npos; pos = line.find(key, pos + 1))
    if (pos == 0 || line[pos - 1] == ' ') return pos;
  return std::string::npos;
}

}  // namespace

std::optional<TempReport> parse_temp_report(const std::string& line) {
  const std::size_t t = find_token(line, "T:");
  if (t == std::string::npos) return std::nullopt;
  const char* begin = line.c_str() + t + 2;
  char* end = nullptr;
  TempReport r;
  r.temp_c = std::strtod(begin, &end);
  if (end == begin) return std::nullopt;
  const std::size_t slash = line.find('/', t);
  if (slash != std::string::npos) r.target_c = std::strtod(line.c_str() + slash + 1, nullptr);
  const std::size_t at = find_token(line, "@:");
  if (at != std::string::npos) r.power = std::atoi(line.c_str() + at + 2);
  return r;
}

HostSession::HostSession(AvrBoard& board) : board_(board) {
  board_.on_uart_byte([this](uint8_t b) { on_byte(b); });
  // A reset loses the command in flight (a real host would time out on it too) and the
  // half-received line.
  board_.on_reset([this] {
    in_flight_.reset();
    partial_.clear();
    awaiting_ok_.clear();
  });
}

void HostSession::send(std::string line, std::function<void(double)> on_ok, std::function<void(double)> on_sent) {
  queue_.push_back(Command{std::move(line) + "\n", std::move(on_ok), std::move(on_sent)});
}

void HostSession::send_now(std::string line, std::function<void(double)> on_sent) {
  urgent_.push_back(Command{std::move(line) + "\n", {}, std::move(on_sent)});
}

bool HostSession::send_bytes(const std::string& text, std::size_t& sent) {
  while (sent < text.size() && board_.uart_accepting())
    if (board_.uart_send(static_cast<uint8_t>(text[sent]))) ++sent;
  return sent == text.size();
}

void HostSession::poll() {
  if (boot_count_ == 0) return;  // the firmware has not said `start` yet
  // A command part-way out is finished first: a line is never split by another.
  const bool in_flight_partial = in_flight_ && bytes_sent_ != 0 && bytes_sent_ < in_flight_->text.size();
  while (!urgent_.empty() && !in_flight_partial) {
    Command& line = urgent_.front();
    if (urgent_bytes_sent_ == 0)
      transcript_.push_back(ReplyLine{board_.time_s(), "> " + line.text.substr(0, line.text.size() - 1)});
    if (!send_bytes(line.text, urgent_bytes_sent_)) return;
    awaiting_ok_.push_back(false);
    if (line.on_sent) line.on_sent(board_.time_s());
    urgent_.pop_front();
    urgent_bytes_sent_ = 0;
  }
  if (!in_flight_) {
    if (queue_.empty()) return;
    in_flight_ = std::move(queue_.front());
    queue_.pop_front();
    const std::string& text = in_flight_->text;
    transcript_.push_back(ReplyLine{board_.time_s(), "> " + text.substr(0, text.size() - 1)});
    bytes_sent_ = 0;
    in_flight_since_s_ = board_.time_s();
  }
  const std::string& text = in_flight_->text;
  const bool was_out = bytes_sent_ == text.size();
  if (send_bytes(text, bytes_sent_) && !was_out) {
    awaiting_ok_.push_back(true);
    if (in_flight_->on_sent) in_flight_->on_sent(board_.time_s());
  }
  if (!waits_for_temperature(text) && board_.time_s() - in_flight_since_s_ > kOkTimeoutS) {
    const std::string cmd = text.substr(0, text.size() - 1);
    problems_.push_back("no ok for \"" + cmd + "\" within " + std::to_string(int(kOkTimeoutS)) + " s");
    in_flight_.reset();
    for (auto it = awaiting_ok_.begin(); it != awaiting_ok_.end(); ++it)
      if (*it) {
        awaiting_ok_.erase(it);
        break;
      }
  }
}

void HostSession::on_byte(uint8_t byte) {
  if (byte == '\r') return;
  if (byte != '\n') {
    partial_.push_back(static_cast<char>(byte));
    return;
  }
  on_complete_line(std::move(partial_));
  partial_.clear();
}

void HostSession::on_complete_line(std::string text) {
  const double now = board_.time_s();
  if (text == "start") ++boot_count_;
  if (auto report = parse_temp_report(text)) {
    report->t_s = now;
    reports_.push_back(*report);
  }
  // oks come in line order: the oldest line awaiting one gets it.
  if (starts_with(text, "ok") && !awaiting_ok_.empty()) {
    const bool is_in_flight = awaiting_ok_.front();
    awaiting_ok_.pop_front();
    if (is_in_flight && in_flight_) {
      auto on_ok = std::move(in_flight_->on_ok);
      in_flight_.reset();
      if (on_ok) on_ok(now);
    }
  }
  transcript_.push_back(ReplyLine{now, "< " + text});
  lines_.push_back(ReplyLine{now, std::move(text)});
  if (line_handler_) line_handler_(lines_.back());
}

}  // namespace sim
