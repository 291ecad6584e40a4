// Connects a JsDevice to a TeleopNode under the live executor (tiller-teleop's I/O glue):
// device reads go straight into the node (no LCM hop), a timerfd re-opens an absent device
// every reopen period, and connection changes and the vehicle's arm state reason (a refusal, a
// takeover) are logged to stderr.
#pragma once

#include "runtime/live.hpp"
#include "teleop/js_device.hpp"
#include "teleop/teleop_node.hpp"

namespace tiller {

class JoystickPump {
 public:
  JoystickPump(JsDevice& device, TeleopNode& node, LiveExecutor& ex, TimeUs reopen_period);
  ~JoystickPump();
  JoystickPump(const JoystickPump&) = delete;
  JoystickPump& operator=(const JoystickPump&) = delete;

 private:
  void on_timer(TimeUs now);
  void on_readable(TimeUs now);
  void handle(JsDevice::Status s, TimeUs now);
  void report_vehicle();  // the vehicle's arm state reason on stderr when it changes

  JsDevice& dev_;
  TeleopNode& node_;
  LiveExecutor& ex_;
  int timer_fd_ = -1;
  int watched_fd_ = -1;
  std::string last_error_;
  bool warned_bad_events_ = false;  // said once on stderr
  std::string reported_reason_, reported_controller_;
};

}  // namespace tiller
