// The simulated board's serial port as a pseudo-terminal: a host program opens its device (or
// the --link symlink) like a USB serial adapter. Raw mode, nothing buffered here: the harness
// reads one byte when the simulated line can take it, so what the host wrote ahead waits in
// the kernel's pty buffer (a few KB, like a USB adapter's), and writes the board's bytes as the
// UART sends them. While no host has the device open the board's output is lost, as it is on a
// board whose USB cable is unplugged.
#pragma once

#include <cstdint>
#include <string>

namespace sim {

class PtyPort {
 public:
  // Opens the pty; `link_path` (may be empty) becomes a symlink to its device. Throws
  // std::runtime_error with the reason if it cannot.
  explicit PtyPort(const std::string& link_path = "");
  ~PtyPort();  // closes the pty, removes the link
  PtyPort(const PtyPort&) = delete;
  PtyPort& operator=(const PtyPort&) = delete;

  const std::string& device() const { return device_; }
  const std::string& link() const { return link_; }

  // Looks (without waiting) whether a host has the device open and whether it wrote bytes.
  void refresh();
  bool host_connected() const { return connected_; }
  // The next byte the host wrote, or -1 (none since the last refresh, or the buffer is empty).
  int read_byte();
  // Writes the board's bytes; those the host's buffer cannot take (or with no host) are lost.
  void write(const std::string& bytes);
  uint64_t bytes_from_host() const { return bytes_in_; }
  uint64_t bytes_to_host() const { return bytes_out_; }
  uint64_t bytes_lost() const { return bytes_lost_; }

 private:
  int master_ = -1;
  std::string device_;
  std::string link_;
  bool connected_ = false;
  bool readable_ = false;
  uint64_t bytes_in_ = 0, bytes_out_ = 0, bytes_lost_ = 0;
};

}  // namespace sim
