// The other end of the joystick device edge: writes a joystick state as Linux js_event records
// (js_device.hpp: 8 bytes {u32 time_ms, s16 value, u8 type, u8 number}) into a FIFO that
// tiller-teleop reads as its device, the way the kernel's joydev driver would: on open every axis
// and button as an INIT event with its current value, then one event per axis or button that
// changed. Closing the FIFO is an unplug for the reader (neutral at once). tiller-stick-script's
// I/O edge.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiller/joystick_state_t.hpp>

namespace tiller {

class JsFifoWriter {
 public:
  // Makes the FIFO if `path` does not exist (mode 0600); a path that exists and is not a FIFO is
  // refused (std::runtime_error naming it).
  explicit JsFifoWriter(std::string path);
  ~JsFifoWriter();
  JsFifoWriter(const JsFifoWriter&) = delete;
  JsFifoWriter& operator=(const JsFifoWriter&) = delete;

  // Blocks until a reader opens the FIFO (tiller-teleop re-opens its device every
  // reopen_period_s). False (errno kept) if interrupted by a signal or refused.
  bool open_for_writing();
  // Writes what changed since the last call (everything as INIT events on the first); time_ms
  // is the records' time stamp. False on a write error (EPIPE: the reader went away).
  bool write(const joystick_state_t& s, std::uint32_t time_ms);
  void close();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  bool first_ = true;
  std::vector<std::int16_t> axes_;
  std::vector<bool> buttons_;
};

}  // namespace tiller
