// The joystick device edge: the Linux joystick ("js") interface read from a path that may be a
// real /dev/input/jsN, a FIFO or a regular file (tests and recordings use the last two).
//
// Format: 8-byte struct js_event {u32 time_ms; s16 value; u8 type; u8 number}, native
// (little-endian) byte order; type BUTTON 0x01, AXIS 0x02, | INIT 0x80 for the synthetic
// events the driver sends on open to report the current state. Axes -32767..32767.
// Why js and not evdev: js gives exactly the joystick (axes and buttons numbered densely, already
// calibrated, with the start-up state as INIT events), the 8-byte record is trivial to record
// and replay through a pipe, and unplugging shows up as ENODEV on read. evdev needs EVIOCGABS
// ranges per axis and a key-code map; its hot-plug advantages (udev) are not needed here since
// we re-open the path on a period.
// Presence: a device or FIFO read that fails with ENODEV (or returns EOF: the FIFO's writer
// closed) means unplugged. A regular file is "present" until it is removed (its link count drops
// to 0); new bytes appended to it are new events (watched with inotify). A FIFO with no writer
// counts as absent. "Connected" is reported only when the first bytes arrive after opening, so
// the INIT events (the stick's position at plug-in) are in the first state the node sees. The
// state's axes and buttons are those reported so far (n_axes = highest axis number seen + 1):
// a start-up state split over several reads leaves the later axes absent, never 0.
// The kernel sends INIT events only on open, before any ordinary event. An INIT event after an
// ordinary one (a driver re-sending its state, a device or writer out of order) is a late INIT:
// counted in the state's late_inits, and read() returns Status::reinit, so teleop goes neutral,
// asks to disarm, and waits for a centred stick (never a jump to the re-sent position).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <tiller/joystick_state_t.hpp>

namespace tiller {

struct JsEvent {
  std::uint32_t time_ms;
  std::int16_t value;
  std::uint8_t type;
  std::uint8_t number;
};
static_assert(sizeof(JsEvent) == 8, "struct js_event is 8 bytes");

inline constexpr std::uint8_t kJsEventButton = 0x01;
inline constexpr std::uint8_t kJsEventAxis = 0x02;
inline constexpr std::uint8_t kJsEventInit = 0x80;
inline constexpr int kJsMaxAxes = 64;
inline constexpr int kJsMaxButtons = 128;

// Applies js_event bytes to a joystick state. Pure. Keeps an incomplete trailing record for
// the next call, so reads may split records anywhere.
class JsEventParser {
 public:
  // Returns the number of events applied to `state` (axes/buttons grow to the highest number seen).
  int feed(const std::uint8_t* data, std::size_t n, joystick_state_t& state);
  void reset() {
    pending_ = 0;
    ordinary_seen_ = false;
  }
  std::int64_t init_events() const { return init_events_; }
  std::int64_t late_init_events() const { return late_init_events_; }
  std::int64_t bad_events() const { return bad_events_; }  // unknown type or number out of range

 private:
  void apply(const JsEvent& e, joystick_state_t& state);
  std::uint8_t buf_[sizeof(JsEvent)] = {};
  std::size_t pending_ = 0;
  std::int64_t init_events_ = 0;
  std::int64_t late_init_events_ = 0;  // INIT after an ordinary event since reset()
  std::int64_t bad_events_ = 0;
  bool ordinary_seen_ = false;
};

class JsDevice {
 public:
  enum class Status { unchanged, connected, changed, disconnected, reinit };

  // `path`: a device, FIFO or file; empty: search /dev/input/js0..31 for `name` (substring).
  JsDevice(std::string path, std::string name);
  ~JsDevice();
  JsDevice(const JsDevice&) = delete;
  JsDevice& operator=(const JsDevice&) = delete;

  // Opens the device if it is closed. True if it is open now (connection is reported by read()).
  bool try_open();
  // Reads everything available (non-blocking) and checks presence. Call when poll_fd() is
  // readable, and on a period for files.
  Status read();
  // The descriptor to wait on: the device or FIFO, or an inotify descriptor for a file; -1 closed.
  int poll_fd() const;
  bool is_open() const { return fd_ >= 0; }
  bool connected() const { return state_.connected; }
  // The current state (connected=false and zeros while absent). utime is not set here.
  const joystick_state_t& state() const { return state_; }
  const std::string& description() const { return description_; }  // path and name
  const std::string& last_error() const { return error_; }
  const JsEventParser& parser() const { return parser_; }

 private:
  void close_device();
  Status disconnect(const std::string& why);

  std::string path_, name_;
  std::string open_path_;
  std::string description_, error_;
  int fd_ = -1;
  int inotify_fd_ = -1;
  bool regular_file_ = false;
  bool is_fifo_ = false;
  bool announce_ = false;  // connected during try_open (a FIFO's first bytes)
  JsEventParser parser_;
  joystick_state_t state_;
};

}  // namespace tiller
