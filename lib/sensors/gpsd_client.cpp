#include "sensors/gpsd_client.hpp"

#include <gps.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace tiller::sensors {

GpsdClient::GpsdClient(const GnssParams& p, GnssNode& node, LiveExecutor& ex)
    : p_(p), node_(node), ex_(&ex), data_(std::make_unique<gps_data_t>()) {
  timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
  if (timer_fd_ >= 0) {
    itimerspec its{};
    its.it_value.tv_sec = p.reconnect_period / kUsPerSecond;
    its.it_value.tv_nsec = (p.reconnect_period % kUsPerSecond) * 1000;
    its.it_interval = its.it_value;
    ::timerfd_settime(timer_fd_, 0, &its, nullptr);
    ex_->add_fd(timer_fd_, [this](TimeUs now) { on_timer(now); });
  }
}

GpsdClient::~GpsdClient() {
  if (open_) {
    ex_->remove_fd(data_->gps_fd);
    ::gps_stream(data_.get(), WATCH_DISABLE, nullptr);
    ::gps_close(data_.get());
  }
  if (timer_fd_ >= 0) {
    ex_->remove_fd(timer_fd_);
    ::close(timer_fd_);
  }
}

std::string GpsdClient::connect(TimeUs now) {
  if (open_) return "";
  std::memset(data_.get(), 0, sizeof(gps_data_t));
  if (::gps_open(p_.host.c_str(), p_.port.c_str(), data_.get()) != 0) {
    const std::string why = "cannot connect to gpsd at " + p_.host + ":" + p_.port + ": " +
                            ::gps_errstr(errno) +
                            " (is gpsd running? `systemctl status gpsd`, or start it with "
                            "`gpsd -N /dev/ttyACM0`)";
    drop(why, now);
    return why;
  }
  ::gps_stream(data_.get(), WATCH_ENABLE | WATCH_JSON, nullptr);
  open_ = true;
  ex_->add_fd(data_->gps_fd, [this](TimeUs t) { pump(t); });
  std::fprintf(stderr, "tiller-gnss: connected to gpsd at %s:%s\n", p_.host.c_str(),
               p_.port.c_str());
  said_.clear();
  node_.set_link("", now);
  return "";
}

namespace {
// The "device" value of a gpsd JSON report ("" when absent).
std::string device_of(const char* raw) {
  const char* d = std::strstr(raw, "\"device\":\"");
  if (d == nullptr) return "";
  d += 10;
  const char* e = std::strchr(d, '"');
  return e ? std::string(d, static_cast<std::size_t>(e - d)) : "";
}
}  // namespace

// gpsd 3.22 (Debian bookworm's) writes an ATT report with a time as
//   {"class":"ATT","device":"/dev/pts/1",,"time":"2026-12-01T12:00:01.200Z""heading":12.500,...}
// (a doubled comma, a missing one): libgps cannot parse it and leaves ATTITUDE_SET unset, so
// every dual-antenna heading but the first (which has no time yet) was lost. Seen here with
// gpsfake and a $GPHDT stream. When the raw report is such an ATT, its heading is read from the
// text, the one field used.
void GpsdClient::att_workaround(gps_data_t& d, const char* raw) {
  if ((d.set & ATTITUDE_SET) || std::strstr(raw, "\"class\":\"ATT\"") == nullptr) return;
  const char* h = std::strstr(raw, "\"heading\":");
  if (h == nullptr) return;
  char* end = nullptr;
  const double deg = std::strtod(h + 10, &end);
  if (end == h + 10) return;
  d.attitude.heading = deg;
  d.set |= ATTITUDE_SET;
  std::snprintf(d.dev.path, sizeof d.dev.path, "%s", device_of(raw).c_str());
}

bool GpsdClient::pump(TimeUs now) {
  if (!open_) return false;
  while (::gps_waiting(data_.get(), 0)) {
    // libgps ORs each report's bits into `set` and keeps the last report's: cleared, a SKY or GST
    // report after a TPV does not look like that TPV again (MODE_SET).
    data_->set = 0;
    if (::gps_read(data_.get(), raw_, sizeof raw_ - 1) < 0) {
      drop("lost the connection to gpsd at " + p_.host + ":" + p_.port, now);
      return false;
    }
    raw_[sizeof raw_ - 1] = '\0';
    att_workaround(*data_, raw_);
    node_.on_gps(*data_, now);
  }
  return true;
}

void GpsdClient::drop(const std::string& why, TimeUs now) {
  if (open_) {
    ex_->remove_fd(data_->gps_fd);
    ::gps_close(data_.get());
    open_ = false;
  }
  if (why != said_) std::fprintf(stderr, "tiller-gnss: %s; retrying\n", why.c_str());
  said_ = why;
  node_.set_link(why, now);
}

void GpsdClient::on_timer(TimeUs now) {
  std::uint64_t n = 0;
  while (::read(timer_fd_, &n, sizeof n) > 0) {
  }
  if (!open_) connect(now);
}

}  // namespace tiller::sensors
