// The cockpit's side of the thruster test (docs/safety.md, "Thruster test"): a page's hold-to-spin
// button becomes thruster_test_t requests on TILLER_THRUSTER_TEST. tiller-mixer's intent gate
// decides whether the thruster moves (armed, the source in control neutral, |command| within its
// cap); this relay only keeps the page's side honest:
//   - one page at a time holds a test (another page is refused until it ends);
//   - every press gets a new test_id (>= 1, increasing): the gate never restarts an ended test;
//   - a press needs confirm: true (the page asked the operator) and |command| <= max_command
//     (the cockpit's own cap, config thruster_test.max_command; the mixer has its own);
//   - the test ends (active = false published at once) when the page lets go, sends a bad value,
//     closes its socket, or is silent for timeout_s (the page repeats every 0.1 s while held);
//     a press that ended so stays ended (its later messages are refused: press again).
// Pure: no clock, no allocation after construction.
#pragma once

#include <cstdint>

#include <tiller/thruster_test_t.hpp>

#include "core/time.hpp"

namespace tiller::cockpit {

struct ThrusterTestParams {
  double max_command = 0.1;  // largest |command| the page may ask (normalised)
  TimeUs timeout = 500'000;  // a held button repeats every 0.1 s; silent this long: ended
};

class ThrusterTestRelay {
 public:
  enum class Result { kRefused, kStarted, kHeld, kEnded, kIgnored };

  explicit ThrusterTestRelay(const ThrusterTestParams& p = {}) : p_(p) { out_.source = "cockpit"; }

  // A page's message: `press` is the page's number for this press (any integer), `active` false
  // when it lets go. kRefused: why() says why (nothing to publish). kStarted, kHeld, kEnded:
  // publish message(). kIgnored: nothing to do (a let-go for no test).
  Result request(int client, std::int64_t press, bool active, bool confirm, int thruster,
                 double command, std::int64_t new_id, TimeUs now);
  // The page's socket closed, or time passed: true when a test ended (publish message()).
  bool client_closed(int client, TimeUs now);
  bool tick(TimeUs now);

  const thruster_test_t& message() const { return out_; }
  const char* why() const { return why_; }
  int client() const { return client_; }
  const ThrusterTestParams& params() const { return p_; }

 private:
  bool end(TimeUs now);

  ThrusterTestParams p_;
  int client_ = -1;         // the page holding a test, or -1
  std::int64_t press_ = 0;  // its press number
  int ended_client_ = -1;   // the last press that ended (refused until a new press)
  std::int64_t ended_press_ = 0;
  TimeUs rx_ = 0;  // its latest message
  thruster_test_t out_{};
  const char* why_ = "";
};

}  // namespace tiller::cockpit
