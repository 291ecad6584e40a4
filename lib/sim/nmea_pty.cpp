#include "sim/nmea_pty.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace tiller::sim {

namespace {
[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error("NMEA pseudo-terminal: " + what + ": " + std::strerror(errno));
}
}  // namespace

NmeaPty::NmeaPty(const std::string& link_path) {
  master_ = posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0) fail("posix_openpt");
  char name[128];
  if (grantpt(master_) != 0 || unlockpt(master_) != 0 ||
      ptsname_r(master_, name, sizeof name) != 0) {
    const int e = errno;
    ::close(master_);
    errno = e;
    fail("grantpt/unlockpt/ptsname_r");
  }
  slave_path_ = name;
  slave_ = ::open(name, O_RDWR | O_NOCTTY);
  if (slave_ < 0) {
    const int e = errno;
    ::close(master_);
    errno = e;
    fail("open " + slave_path_);
  }
  termios t{};
  if (tcgetattr(slave_, &t) == 0) {
    cfmakeraw(&t);
    tcsetattr(slave_, TCSANOW, &t);
  }
  ::fcntl(master_, F_SETFL, ::fcntl(master_, F_GETFL) | O_NONBLOCK);
  if (!link_path.empty()) {
    struct stat st {};
    if (::lstat(link_path.c_str(), &st) == 0) {
      if (!S_ISLNK(st.st_mode)) {
        ::close(slave_);
        ::close(master_);
        errno = EEXIST;
        fail("--nmea-link " + link_path + " exists and is not a symlink (refusing to replace it)");
      }
      ::unlink(link_path.c_str());
    }
    if (::symlink(slave_path_.c_str(), link_path.c_str()) != 0) {
      const int e = errno;
      ::close(slave_);
      ::close(master_);
      errno = e;
      fail("symlink " + link_path + " -> " + slave_path_);
    }
    link_path_ = link_path;
  }
}

NmeaPty::~NmeaPty() {
  if (!link_path_.empty()) ::unlink(link_path_.c_str());
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
}

void NmeaPty::write(const char* data, std::size_t n) {
  // The simulator holds the slave open and nobody may be reading: what gpsd does not take stays
  // in the terminal's buffer. Drop it first so gpsd always reads the newest epoch.
  if (slave_ >= 0) tcflush(slave_, TCIFLUSH);
  const ssize_t w = ::write(master_, data, n);
  if (w == static_cast<ssize_t>(n)) {
    ++written_;
  } else {
    ++dropped_;
  }
}

}  // namespace tiller::sim
