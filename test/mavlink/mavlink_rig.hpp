// The tests' ground station and node rig for tiller-mavlink (test/mavlink): a bus that keeps what
// the node publishes, a station that packs (signed) frames, the node with its frames out decoded.
#pragma once

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mavlink/frame.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mavlink/mavlink_node.hpp"
#include "runtime/node.hpp"

namespace tiller::mavlink {

inline std::string hex(const std::uint8_t* d, std::size_t n) {
  std::string s;
  char b[3];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, "%02x", d[i]);
    s += b;
  }
  return s;
}

inline Secret test_key() {
  Secret k{};
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(i + 1);
  return k;
}

inline constexpr TimeUs kT0 = 1700000000000000;  // 2023-11-14, us since 1970

class CollectBus : public Bus {
 public:
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    events.emplace_back(std::string(channel), std::vector<std::uint8_t>(data, data + size));
  }
  template <class Msg>
  std::vector<Msg> on(const std::string& ch) const {
    std::vector<Msg> out;
    for (const auto& [c, b] : events) {
      if (c != ch) continue;
      Msg m;
      m.decode(b.data(), 0, static_cast<int>(b.size()));
      out.push_back(m);
    }
    return out;
  }
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> events;
};

// A ground station: packs frames (signed with the key, or not) and reads the vehicle's.
struct Station {
  explicit Station(std::optional<Secret> key, std::uint8_t sysid = 255) : w(sysid, 190, key, 1) {}
  FrameWriter w;
  std::vector<std::uint8_t> frame(mavlink_message_t& m, TimeUs now) {
    std::uint8_t out[kMaxFrame];
    const std::size_t n = w.finish(m, now, out);
    return {out, out + n};
  }
  std::vector<std::uint8_t> command(std::uint16_t cmd, float p1, float p2, TimeUs now) {
    mavlink_message_t m;
    mavlink_msg_command_long_pack_status(w.sysid(), w.compid(), w.status(), &m, 1, 1, cmd, 0, p1,
                                         p2, 0, 0, 0, 0, 0);
    return frame(m, now);
  }
  std::vector<std::uint8_t> manual(std::int16_t x, std::int16_t r, TimeUs now) {
    mavlink_message_t m;
    mavlink_msg_manual_control_pack_status(w.sysid(), w.compid(), w.status(), &m, 1, x, 0, 500, r,
                                           0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
    return frame(m, now);
  }
};

struct Rig {
  explicit Rig(bool require = true, std::vector<GainParam> gains = {}) {
    MavlinkParams p;
    p.gains = std::move(gains);
    for (std::size_t i = 0; i < kParamCount; ++i) p.params[i] = kParams[i].fallback;
    p.secret = test_key();
    p.require_signed = require;
    p.station = "qgc";
    node = std::make_unique<MavlinkNode>(p);
    node->attach(&bus);
    node->set_sink([this](const std::uint8_t* d, std::size_t n) {
      FrameReader r;
      for (std::size_t i = 0; i < n; ++i)
        if (r.feed(d[i])) out.push_back(*r.frame().msg);
    });
  }
  void in(const std::vector<std::uint8_t>& f, TimeUs now) {
    node->on_bytes(f.data(), f.size(), true, now);
  }
  int count(std::uint32_t msgid) const {
    int n = 0;
    for (const auto& m : out) n += m.msgid == msgid;
    return n;
  }
  std::string texts() const {
    std::string s;
    for (const auto& m : out) {
      if (m.msgid != MAVLINK_MSG_ID_STATUSTEXT) continue;
      char t[51] = {};
      mavlink_msg_statustext_get_text(&m, t);
      s += std::string(t) + "\n";
    }
    return s;
  }
  CollectBus bus;
  std::unique_ptr<MavlinkNode> node;
  std::vector<mavlink_message_t> out;
};

}  // namespace tiller::mavlink
