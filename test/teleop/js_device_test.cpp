// The js device edge: js_event parsing (split reads, INIT, bad records), and presence through a
// FIFO (writer closes -> unplugged, no writer -> absent, writer back -> connected) and a
// regular file (appended bytes are events, removal -> unplugged). No /dev/input here.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "teleop/js_device.hpp"
#include "teleop_rig.hpp"

namespace tiller {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("tiller_js_" + std::to_string(getpid()) + "_" + name))
      .string();
}

std::vector<std::uint8_t> event(std::uint32_t t, std::uint8_t type, std::uint8_t n,
                                std::int16_t v) {
  JsEvent e{t, v, type, n};
  std::vector<std::uint8_t> b(8);
  std::memcpy(b.data(), &e, 8);
  return b;
}

void write_all(int fd, const std::vector<std::uint8_t>& b) {
  ASSERT_EQ(::write(fd, b.data(), b.size()), static_cast<ssize_t>(b.size()));
}

bool readable(int fd) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, 200) == 1;
}

TEST(JsEventParser, SplitReadsGiveTheSameState) {
  const auto bytes = test::read_bytes(test::data_path("e3dp_positions.js"));
  ASSERT_EQ(bytes.size() % 8, 0u);
  joystick_state_t whole{}, split{};
  JsEventParser a, b;
  EXPECT_EQ(a.feed(bytes.data(), bytes.size(), whole), static_cast<int>(bytes.size() / 8));
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    b.feed(bytes.data() + i, std::min<std::size_t>(3, bytes.size() - i), split);
  }
  EXPECT_EQ(whole.n_axes, 6);
  EXPECT_EQ(whole.n_buttons, 12);
  EXPECT_EQ(whole.axes, split.axes);
  EXPECT_EQ(whole.buttons, split.buttons);
  EXPECT_EQ(whole.axes[3], 32767);  // the slider's INIT value
  EXPECT_EQ(a.init_events(), 18);
  EXPECT_EQ(b.init_events(), 18);
}

TEST(JsEventParser, BadRecordsCountedNotApplied) {
  joystick_state_t s{};
  JsEventParser p;
  auto e1 = event(0, 0x04, 0, 5);              // unknown type
  auto e2 = event(0, kJsEventAxis, 70, 5);     // axis number out of range
  auto e3 = event(0, kJsEventButton, 200, 1);  // button number out of range
  auto e4 = event(0, kJsEventAxis | kJsEventInit, 2, -100);
  for (auto* e : {&e1, &e2, &e3, &e4}) p.feed(e->data(), e->size(), s);
  EXPECT_EQ(p.bad_events(), 3);
  EXPECT_EQ(s.n_axes, 3);
  EXPECT_EQ(s.axes[2], -100);
  EXPECT_EQ(s.n_buttons, 0);
}

TEST(JsDevice, MissingPathIsAbsentWithAMessage) {
  JsDevice d("/nonexistent/js0", "");
  EXPECT_FALSE(d.try_open());
  EXPECT_NE(d.last_error().find("/nonexistent/js0"), std::string::npos);
  EXPECT_FALSE(d.connected());
  JsDevice byname("", "Extreme 3D");
  EXPECT_FALSE(byname.try_open());  // no /dev/input here
  EXPECT_NE(byname.last_error().find("Extreme 3D"), std::string::npos);
}

TEST(JsDevice, FifoWriterClosingIsUnplugAndReturningIsReplug) {
  const std::string path = temp_path("fifo");
  ::unlink(path.c_str());
  ASSERT_EQ(mkfifo(path.c_str(), 0600), 0);
  JsDevice d(path, "");
  // No writer yet: absent.
  EXPECT_FALSE(d.try_open());
  EXPECT_NE(d.last_error().find("no writer"), std::string::npos);
  // A writer appears (O_RDWR never blocks) and sends the INIT block.
  int w = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
  ASSERT_GE(w, 0);
  EXPECT_TRUE(d.try_open());
  EXPECT_EQ(d.read(), JsDevice::Status::unchanged);  // open, but nothing heard yet
  EXPECT_FALSE(d.connected());
  const auto rec = test::read_bytes(test::data_path("e3dp_init_deflected.js"));
  write_all(w, std::vector<std::uint8_t>(rec.begin(), rec.begin() + 18 * 8));  // the INIT block
  ASSERT_TRUE(readable(d.poll_fd()));
  EXPECT_EQ(d.read(), JsDevice::Status::connected);
  EXPECT_TRUE(d.connected());
  EXPECT_EQ(d.state().axes[1], -32767);
  write_all(w, event(5, kJsEventAxis, 1, 0));
  ASSERT_TRUE(readable(d.poll_fd()));
  EXPECT_EQ(d.read(), JsDevice::Status::changed);
  EXPECT_EQ(d.state().axes[1], 0);
  // Pull the plug: the writer closes -> EOF -> disconnected, zeros, device closed.
  ::close(w);
  ASSERT_TRUE(readable(d.poll_fd()));
  EXPECT_EQ(d.read(), JsDevice::Status::disconnected);
  EXPECT_FALSE(d.connected());
  EXPECT_FALSE(d.is_open());
  EXPECT_EQ(d.state().axes[3], 0);
  EXPECT_FALSE(d.try_open());  // still no writer
  // Plug back in.
  w = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
  write_all(w, event(9, kJsEventAxis | kJsEventInit, 0, 1234));
  EXPECT_TRUE(d.try_open());
  EXPECT_EQ(d.read(), JsDevice::Status::connected);
  EXPECT_EQ(d.state().axes[0], 1234);
  ::close(w);
  ::unlink(path.c_str());
}

TEST(JsDevice, FileAppendIsEventsAndRemovalIsUnplug) {
  const std::string path = temp_path("file");
  const auto init = test::read_bytes(test::data_path("e3dp_positions.js"));
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    std::fwrite(init.data(), 1, 18 * 8, f);
    std::fclose(f);
  }
  JsDevice d(path, "");
  ASSERT_TRUE(d.try_open());
  EXPECT_EQ(d.read(), JsDevice::Status::connected);
  EXPECT_EQ(d.state().n_axes, 6);
  EXPECT_EQ(d.read(), JsDevice::Status::unchanged);  // end of file: wait for more, still present
  EXPECT_TRUE(d.connected());
  const int w = ::open(path.c_str(), O_WRONLY | O_APPEND);
  write_all(w, event(1100, kJsEventAxis, 1, -32767));
  ASSERT_TRUE(readable(d.poll_fd()));  // inotify says modified
  EXPECT_EQ(d.read(), JsDevice::Status::changed);
  EXPECT_EQ(d.state().axes[1], -32767);
  ::close(w);
  ::unlink(path.c_str());
  ASSERT_TRUE(readable(d.poll_fd()));  // inotify: link count changed
  EXPECT_EQ(d.read(), JsDevice::Status::disconnected);
  EXPECT_EQ(d.state().axes[1], 0);
  EXPECT_FALSE(d.try_open());
}

}  // namespace
}  // namespace tiller
