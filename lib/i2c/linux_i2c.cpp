#include "i2c/linux_i2c.hpp"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tiller::i2c {

int LinuxI2c::open_adapter() {
  const int fd = ::open(path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) {
    failed_at_ = Step::kOpen;
    return errno;
  }
  unsigned long funcs = 0;
  if (::ioctl(fd, I2C_FUNCS, &funcs) < 0) {
    const int e = errno;
    ::close(fd);
    failed_at_ = Step::kFuncs;
    return e;
  }
  if ((funcs & I2C_FUNC_I2C) == 0) {
    ::close(fd);
    failed_at_ = Step::kPlainI2c;
    return EOPNOTSUPP;
  }
  fd_ = fd;
  return 0;
}

LinuxI2c::LinuxI2c(const std::string& path, IfMissing if_missing) : path_(path) {
  const int e = open_adapter();
  if (e == 0) return;
  std::string hint;
  if (e == ENOENT) {
    hint =
        " (is the i2c-dev module loaded? `modprobe i2c-dev`; on a Raspberry Pi enable I2C "
        "with raspi-config; `ls /dev/i2c-*` lists the buses)";
  } else if (e == EACCES || e == EPERM) {
    hint = " (add the user to the group that owns it, usually `i2c`, or run as root)";
  }
  if (failed_at_ == Step::kPlainI2c) {
    open_error_ = path +
                  ": the adapter only does SMBus, not plain I2C transactions "
                  "(I2C_RDWR); the ESC and sensor protocols need plain I2C";
  } else if (failed_at_ == Step::kFuncs) {
    open_error_ = path + " is not an i2c-dev adapter (I2C_FUNCS: " + std::strerror(e) + ")";
  } else {
    open_error_ = "cannot open I2C bus " + path + ": " + std::strerror(e) + hint;
  }
  if (if_missing == IfMissing::kThrow) throw std::runtime_error(open_error_);
}

LinuxI2c::~LinuxI2c() {
  if (fd_ >= 0) ::close(fd_);
}

int LinuxI2c::write(std::uint8_t addr, const std::uint8_t* data, std::size_t n) {
  if (const int e = ensure_open()) return e;
  i2c_msg msg{};
  msg.addr = addr;
  msg.flags = 0;
  msg.len = static_cast<__u16>(n);
  msg.buf = const_cast<__u8*>(data);  // the kernel only reads a write message's buffer
  i2c_rdwr_ioctl_data xfer{&msg, 1};
  return ::ioctl(fd_, I2C_RDWR, &xfer) < 0 ? errno : 0;
}

int LinuxI2c::write_read(std::uint8_t addr, const std::uint8_t* w, std::size_t wn, std::uint8_t* r,
                         std::size_t rn) {
  if (const int e = ensure_open()) return e;
  i2c_msg msgs[2]{};
  msgs[0].addr = addr;
  msgs[0].flags = 0;
  msgs[0].len = static_cast<__u16>(wn);
  msgs[0].buf = const_cast<__u8*>(w);
  msgs[1].addr = addr;
  msgs[1].flags = I2C_M_RD;
  msgs[1].len = static_cast<__u16>(rn);
  msgs[1].buf = r;
  i2c_rdwr_ioctl_data xfer{msgs, 2};
  return ::ioctl(fd_, I2C_RDWR, &xfer) < 0 ? errno : 0;
}

int LinuxI2c::claim(std::uint8_t addr) {
  if (const int e = ensure_open()) return e;
  return ::ioctl(fd_, I2C_SLAVE, static_cast<unsigned long>(addr)) < 0 ? errno : 0;
}

void LinuxI2c::wait_us(std::int64_t us) {
  timespec ts{static_cast<time_t>(us / 1'000'000), static_cast<long>((us % 1'000'000) * 1000)};
  while (::nanosleep(&ts, &ts) < 0 && errno == EINTR) {
  }
}

}  // namespace tiller::i2c
