// Helpers for the end-to-end pilot test and the latency benchmark: start the real tiller-*
// processes (killed with the test), write js_events into a FIFO in place of /dev/input/js0,
// and listen to LCM. Everything runs inside the private network namespace of tools/netns-run.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "teleop/js_device.hpp"

namespace tiller::e2e {

inline constexpr const char* kUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

inline std::int64_t realtime_us() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000 + ts.tv_nsec / 1000;
}

inline void sleep_ms(double ms) {
  std::this_thread::sleep_for(std::chrono::microseconds(static_cast<std::int64_t>(ms * 1000)));
}

// A child process; SIGTERM on destruction; dies with its parent (PDEATHSIG). Its stdout goes to
// /dev/null (quiet) or is inherited; with `out_file`, stdout and stderr go to that file.
class Proc {
 public:
  Proc(const std::string& exe, const std::vector<std::string>& args, bool quiet = true,
       const std::string& out_file = "") {
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (!out_file.empty()) {
        const int o = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(o, 1);
        dup2(o, 2);
      } else if (quiet) {
        const int n = ::open("/dev/null", O_WRONLY);
        dup2(n, 1);
      }
      std::vector<char*> argv;
      argv.push_back(const_cast<char*>(exe.c_str()));
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(exe.c_str(), argv.data());
      _exit(127);
    }
  }
  ~Proc() { stop(); }
  Proc(const Proc&) = delete;
  Proc& operator=(const Proc&) = delete;
  bool running() { return pid_ > 0 && waitpid(pid_, &status_, WNOHANG) == 0; }
  // SIGTERM and wait; returns the exit status (or -1).
  int stop() {
    if (pid_ <= 0) return status_;
    if (waitpid(pid_, &status_, WNOHANG) == 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, &status_, 0);
    }
    pid_ = -1;
    return status_;
  }

 private:
  pid_t pid_ = -1;
  int status_ = -1;
};

// The writer end of a FIFO that tiller-teleop reads as its joystick. O_RDWR never blocks and
// keeps the FIFO alive; close() is "pulling the plug" (the reader sees EOF).
class FifoStick {
 public:
  explicit FifoStick(std::string path) : path_(std::move(path)) {
    ::unlink(path_.c_str());
    if (mkfifo(path_.c_str(), 0600) != 0) throw std::runtime_error("mkfifo " + path_);
  }
  ~FifoStick() {
    unplug();
    ::unlink(path_.c_str());
  }
  const std::string& path() const { return path_; }
  void plug() {
    if (fd_ < 0) fd_ = ::open(path_.c_str(), O_RDWR | O_NONBLOCK);
  }
  void unplug() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  // Writes events in one write (one read on the other side); returns the time just before.
  std::int64_t write(const std::vector<JsEvent>& ev) {
    const std::int64_t t = realtime_us();
    if (::write(fd_, ev.data(), ev.size() * sizeof(JsEvent)) < 0) throw std::runtime_error("write");
    return t;
  }
  std::int64_t axis(int n, int v) {
    return write(
        {JsEvent{ms(), static_cast<std::int16_t>(v), kJsEventAxis, static_cast<std::uint8_t>(n)}});
  }
  std::int64_t button(int n, bool on) {
    return write({JsEvent{ms(), static_cast<std::int16_t>(on), kJsEventButton,
                          static_cast<std::uint8_t>(n)}});
  }
  // The INIT block of an Extreme 3D Pro: 12 buttons released, axes as given (6).
  std::int64_t init(const std::vector<int>& axes) {
    std::vector<JsEvent> ev;
    for (int b = 0; b < 12; ++b) {
      ev.push_back(JsEvent{ms(), 0, static_cast<std::uint8_t>(kJsEventButton | kJsEventInit),
                           static_cast<std::uint8_t>(b)});
    }
    for (std::size_t a = 0; a < axes.size(); ++a) {
      ev.push_back(JsEvent{ms(), static_cast<std::int16_t>(axes[a]),
                           static_cast<std::uint8_t>(kJsEventAxis | kJsEventInit),
                           static_cast<std::uint8_t>(a)});
    }
    return write(ev);
  }

 private:
  static std::uint32_t ms() { return static_cast<std::uint32_t>(realtime_us() / 1000); }
  std::string path_;
  int fd_ = -1;
};

}  // namespace tiller::e2e
