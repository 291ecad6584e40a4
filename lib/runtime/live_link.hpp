// One node on LCM inside a program that runs its own event loop (tiller-launch: its
// LaunchMonitor, launch/monitor.hpp). The same transport rules as the live executor
// (runtime/live.hpp): opens LCM at `url`, subscribes to the node's channels, checks each
// message with the signing policy (auth/verifier.hpp; refusals and the node's sender rules are
// counted as rejected.auth.<why>), strips the 48-byte trailer and delivers the message told
// its receive time; ticks the node on its grid (told the grid time; a late loop runs only the
// latest grid point) and publishes what it says, signed as the node when there is a key.
// Reads the wall clock. The host loop polls fd() and calls handle() when it is readable and
// tick() each time round.
#pragma once

#include <lcm/lcm.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "auth/trailer.hpp"
#include "auth/verifier.hpp"
#include "runtime/node.hpp"

namespace tiller {

class LiveLink : public Bus {
 public:
  // Throws std::runtime_error naming the URL when LCM cannot be opened.
  LiveLink(const std::string& url, const auth::Policy& policy, Node& node);
  ~LiveLink() override;
  LiveLink(const LiveLink&) = delete;
  LiveLink& operator=(const LiveLink&) = delete;

  int fd() const;
  // Delivers the messages waiting on fd() (at most 1000), then tick(now).
  void handle();
  // Runs the node's tick when its grid time has come.
  void tick(TimeUs now);
  TimeUs next_tick() const { return next_tick_; }  // us since the epoch
  void publish(std::string_view channel, const std::uint8_t* data, int size) override;

 private:
  static void on_message(const lcm_recv_buf_t* rbuf, const char* channel, void* self);
  lcm_t* lcm_ = nullptr;
  auth::Verifier verifier_;
  std::optional<auth::Signer> signer_;
  Node& node_;
  std::array<std::int64_t*, auth::kVerdicts> refused_{};
  std::int64_t* sender_ = nullptr;
  TimeUs next_tick_ = 0;
  std::string channel_;
  std::vector<std::uint8_t> buf_;
};

}  // namespace tiller
