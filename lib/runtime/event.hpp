// One recorded or published LCM message: channel, time (us) and encoded bytes. The unit of
// exchange between executors, logs and the replay tools.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiller/count_guard.hpp>

#include "core/time.hpp"

namespace tiller {

struct Event {
  std::string channel;
  TimeUs time = 0;
  std::vector<std::uint8_t> data;
};

// Decodes an Event's bytes into a message; returns false if the bytes are not a Msg. Array
// counts that cannot fit in the bytes are refused before lcm-gen's decoder resizes to them.
template <class Msg>
bool decode(const Event& e, Msg& out) {
  const int n = static_cast<int>(e.data.size());
  if (!counts_fit<Msg>(e.data.data(), n)) return false;
  return out.decode(e.data.data(), 0, n) == n;
}

// Encodes a message into an Event.
template <class Msg>
Event encode(const std::string& channel, TimeUs time, const Msg& msg) {
  Event e{channel, time, {}};
  e.data.resize(static_cast<std::size_t>(msg.getEncodedSize()));
  msg.encode(e.data.data(), 0, static_cast<int>(e.data.size()));
  return e;
}

}  // namespace tiller
