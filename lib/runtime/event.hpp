// One recorded or published LCM message: channel, time (us) and encoded bytes. The unit of
// exchange between executors, logs and the replay tools.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/time.hpp"

namespace tiller {

struct Event {
  std::string channel;
  TimeUs time = 0;
  std::vector<std::uint8_t> data;
};

// Decodes an Event's bytes into a message; returns false if the bytes are not a Msg.
template <class Msg>
bool decode(const Event& e, Msg& out) {
  const int n = static_cast<int>(e.data.size());
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
