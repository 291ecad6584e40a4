// tiller-leak's logic: leak probes on GPIO input lines -> leak_t on TILLER_LEAK at rate_hz.
//
// Each probe is a line (chip, offset) read through GpioInputs (sensors/gpio.hpp; libgpiod on a
// vehicle), active-high or active-low by config (a Blue Robotics SOS probe board drives its
// output high when wet). Wet is reported at the first read at the active level; it clears only
// after the line has read dry for dry_after_s without a break (a drip that comes and goes stays
// wet). The driver does not latch a leak: the failsafe's vehicle_status_t.latched does (until a
// restart). A probe whose line cannot be requested or read is reported unreadable and wet
// (fail safe, as the message contract says), counted ("gpio.request_failures",
// "gpio.read_errors"), asked for again every retry period, and puts the heartbeat in FAULT
// naming the probe, the chip and the line. Time comes only from the executor.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tiller/leak_t.hpp>

#include "core/time.hpp"
#include "runtime/node.hpp"
#include "sensors/gpio.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct LeakProbe {
  std::string name;
  std::string chip = "gpiochip0";
  unsigned line = 0;
  bool active_high = true;
  Bias bias = Bias::as_is;
};

struct LeakParams {
  std::vector<LeakProbe> probes;
  double rate_hz = 10;
  TimeUs dry_after = 2 * kUsPerSecond;
  std::string channel = "TILLER_LEAK";
  TimeUs retry_period = kUsPerSecond;
};

// Strict loader: every error names the file, the key and what was expected.
LeakParams load_leak_params(const config::Value& root);
LeakParams load_leak_file(const std::string& path);

class LeakNode : public Node {
 public:
  LeakNode(const LeakParams& p, GpioInputs& gpio);
  ~LeakNode() override;  // gives its lines back
  const leak_t& last() const { return msg_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  struct Probe {
    LeakProbe cfg;
    std::string where;  // "probe main_tube (gpiochip0 line 17)"
    int handle = -1;
    TimeUs next_request = INT64_MIN;
    TimeUs last_active = INT64_MIN;
    std::string error;
  };
  void update_health();

  LeakParams p_;
  GpioInputs& gpio_;
  std::vector<Probe> probes_;
  leak_t msg_{};
  std::int64_t *request_failures_, *read_errors_, *wet_events_, *rejected_;
  std::uint64_t health_key_ = ~0ull;  // readable bits | wet bits << 32 of the last status
  std::string status_;
};

}  // namespace tiller::sensors
