#include "cockpit/thruster_test.hpp"

#include <cmath>

namespace tiller::cockpit {

ThrusterTestRelay::Result ThrusterTestRelay::request(int client, std::int64_t press, bool active,
                                                     bool confirm, int thruster, double command,
                                                     std::int64_t new_id, TimeUs now) {
  why_ = "";
  if (client_ >= 0 && client != client_) {
    why_ = "another page is running a thruster test";
    return Result::kRefused;
  }
  if (!active) return client_ == client && end(now) ? Result::kEnded : Result::kIgnored;
  if (client_ < 0 && client == ended_client_ && press == ended_press_) {
    why_ = "this press ended (silent, or a bad value): let go and press again";
    return Result::kRefused;
  }
  const bool same = client_ == client && press == press_;
  const char* bad = !confirm                        ? "a thruster test needs \"confirm\": true"
                    : thruster < 0 || thruster > 15 ? "thruster: an index 0..15"
                    : !(std::fabs(command) <= p_.max_command)
                        ? "command beyond the cockpit's thruster_test.max_command"
                        : nullptr;
  if (bad != nullptr) {
    why_ = bad;
    // A bad value ends a running test at once (publish the end, and say why).
    return client_ == client && end(now) ? Result::kEnded : Result::kRefused;
  }
  if (same && thruster != out_.thruster) {  // one thruster per press
    why_ = "another thruster in the same press (let go first)";
    end(now);
    return Result::kEnded;
  }
  const bool start = !same;
  if (start) out_.test_id = new_id;
  client_ = client;
  press_ = press;
  rx_ = now;
  out_.utime = now;
  out_.active = true;
  out_.thruster = thruster;
  out_.command = command;
  return start ? Result::kStarted : Result::kHeld;
}

bool ThrusterTestRelay::end(TimeUs now) {
  if (client_ < 0) return false;
  ended_client_ = client_;
  ended_press_ = press_;
  client_ = -1;
  out_.utime = now;
  out_.active = false;
  out_.command = 0.0;
  return true;
}

bool ThrusterTestRelay::client_closed(int client, TimeUs now) {
  return client == client_ && end(now);
}

bool ThrusterTestRelay::tick(TimeUs now) {
  return client_ >= 0 && now - rx_ > p_.timeout && end(now);
}

}  // namespace tiller::cockpit
