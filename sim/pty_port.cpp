#include "sim/pty_port.h"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace sim {
namespace {

std::runtime_error os_error(const std::string& what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}

// Raw 8N1 at 115200 on the device side, so a host that does not set the line up itself
// (e.g. `cat`) sees the bytes unchanged. The setting stays with the pty while we hold the master.
void make_raw(const std::string& device) {
  const int slave = ::open(device.c_str(), O_RDWR | O_NOCTTY);
  if (slave < 0) throw os_error("cannot open " + device);
  termios t{};
  if (tcgetattr(slave, &t) == 0) {
    cfmakeraw(&t);
    cfsetispeed(&t, B115200);
    cfsetospeed(&t, B115200);
    tcsetattr(slave, TCSANOW, &t);
  }
  ::close(slave);
}

}  // namespace

PtyPort::PtyPort(const std::string& link_path) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (master_ < 0) throw os_error("posix_openpt");
  if (grantpt(master_) != 0 || unlockpt(master_) != 0) {
    ::close(master_);
    throw os_error("grantpt/unlockpt");
  }
  device_ = ptsname(master_);
  make_raw(device_);
  if (!link_path.empty()) {
    ::unlink(link_path.c_str());  // a stale link from an earlier session
    if (::symlink(device_.c_str(), link_path.c_str()) != 0) {
      ::close(master_);
      throw os_error("cannot create the link " + link_path);
    }
    link_ = link_path;
  }
}

PtyPort::~PtyPort() {
  if (!link_.empty()) ::unlink(link_.c_str());
  if (master_ >= 0) ::close(master_);
}

void PtyPort::refresh() {
  pollfd p{master_, POLLIN, 0};
  if (::poll(&p, 1, 0) < 0) return;
  // With no slave open the master reports a hang-up (and reads fail with EIO).
  connected_ = (p.revents & POLLHUP) == 0;
  readable_ = connected_ && (p.revents & POLLIN) != 0;
}

int PtyPort::read_byte() {
  if (!readable_) return -1;
  uint8_t byte = 0;
  if (::read(master_, &byte, 1) != 1) {
    readable_ = false;
    return -1;
  }
  ++bytes_in_;
  return byte;
}

void PtyPort::write(const std::string& bytes) {
  if (bytes.empty()) return;
  if (!connected_) {
    bytes_lost_ += bytes.size();
    return;
  }
  const ssize_t n = ::write(master_, bytes.data(), bytes.size());
  const std::size_t written = n > 0 ? static_cast<std::size_t>(n) : 0;
  bytes_out_ += written;
  bytes_lost_ += bytes.size() - written;
}

}  // namespace sim
