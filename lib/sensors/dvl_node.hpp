// tiller-dvl's logic: the Water Linked DVL-A50's TCP JSON lines (sensors/dvl_a50.hpp, Water
// Linked, "DVL protocol", docs.waterlinked.com) -> dvl_t on TILLER_DVL, one message per valid
// velocity report.
//
// Frames and units: the DVL reports vx vy vz (m/s) in its own frame (x forward, y right, z down
// when it is mounted as Water Linked's default, or after the mounting rotation configured in the
// DVL itself). The node rotates them into body FRD by the configured mounting: roll, pitch, yaw
// (deg in the config, rad here) of the DVL frame relative to the body, Fossen's zyx order,
// v_body = R v_dvl with R = Rz(yaw) Ry(pitch) Rx(roll) (a DVL turned 90 deg to starboard, yaw 90:
// its vx is the body's v). All 0 (the default): the DVL's frame is the body's. The covariance
// ((m/s)^2) is rotated too, R C R^T; a report without one (json_v2) gets diag(fom^2).
// utime = receive time - latency_s (clamped at 0): the ping's centre on this computer's clock.
// bottom_lock = velocity_valid && status == 0. Without bottom lock the message carries velocity
// 0, covariance 0 (unknown) and altitude -1, as the contract (lcmtypes/dvl_t.lcm) requires; with
// lock a negative altitude (none) is -1. beams_valid: transducers with beam_valid (-1: not
// reported). A fom above max_fom is published as it is (tiller-nav applies its own limit),
// counted in dvl.fom_high and shown in the heartbeat (DEGRADED).
// The DVL's own dead reckoning (position_local) is counted (lines.dead_reckoning) and not
// published: Tiller's estimator integrates the velocity itself.
// Counted drops (the process keeps running): a line that is not a JSON object with a type
// (rejected.line.malformed), a report with a missing, mistyped or out-of-range field
// (rejected.line.invalid), a message refused by checks::check (rejected.velocity.invalid); other
// report types (command responses, "imu") are counted in lines.ignored. Lock transitions:
// dvl.lock_lost (a report without lock after one with), dvl.lock_regained (with lock after one
// without). The glue (sensors/dvl_link.hpp) reports the connection with set_link() and its
// counters with count_link().
// Health: OK "bottom lock, altitude 3.2 m, fom 0.004 m/s"; DEGRADED "no bottom lock (altitude
// none, status 0)" or a fom above max_fom; FAULT "no velocity report for 2.0 s (connected to
// HOST:PORT)" after timeout_s without a published report (checked at each tick, 10 Hz), and
// "not connected to HOST:PORT: <why>" while the glue says the connection is down.
// No clock: time comes with each line and each tick. Not allocation-free per line: the parser
// (nlohmann::json) builds a JSON tree for each line; the node itself reuses its message and its
// status text.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include <tiller/dvl_t.hpp>

#include "core/time.hpp"
#include "runtime/node.hpp"
#include "sensors/dvl_a50.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct DvlParams {
  std::string host = "192.168.194.95";  // Water Linked's default static IP
  int port = 16171;                     // the JSON protocol's TCP port
  std::string channel = "TILLER_DVL";
  // The DVL frame relative to the body, rad (config: mounting.roll_deg, pitch_deg, yaw_deg).
  double roll = 0, pitch = 0, yaw = 0;
  double latency_s = 0;      // receive time - this = the message's utime
  double timeout_s = 1.0;    // no published report for this long: FAULT
  double max_fom = 0.1;      // m/s; above it: counted (dvl.fom_high), DEGRADED, still published
  double reconnect_s = 1.0;  // a lost connection is tried again no sooner than this
  double connect_timeout_s = 3.0;  // a connection not made within this is given up
  std::size_t max_line = 16384;    // bytes; a longer line is dropped (lines.overlong)
};

// Strict loader: every error names the file, the key and what was expected.
DvlParams load_dvl_params(const config::Value& root);
DvlParams load_dvl_file(const std::string& path);

class DvlNode : public Node {
 public:
  explicit DvlNode(const DvlParams& p);
  // One line from the DVL (without its end of line), received at `now`. Never throws.
  void feed(std::string_view line, TimeUs now);
  // The glue's word on the TCP connection: up, or down and why.
  void set_link(bool up, const std::string& why, TimeUs now);
  // The glue's counters, copied into the heartbeat (link.connects, link.disconnects,
  // lines.overlong).
  void count_link(std::int64_t connects, std::int64_t disconnects, std::int64_t overlong);
  const dvl_t& last() const { return msg_; }
  const DvlParams& params() const { return p_; }
  // The mounting rotation, row-major (v_body = R v_dvl).
  const std::array<double, 9>& rotation() const { return r_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  void on_velocity(const DvlVelocity& v, TimeUs now);
  void update_health(TimeUs now);
  void say_once(int kind, const char* what, const std::string& why);
  DvlParams p_;
  std::array<double, 9> r_{};
  dvl_t msg_{};
  std::string where_;  // "192.168.194.95:16171"
  std::string status_;
  bool link_up_ = false;
  std::string link_why_ = "not connected yet";
  TimeUs since_ = 0;           // the link came up, or the last published report
  bool have_report_ = false;   // a report was published since the link came up
  int last_lock_ = -1;         // -1: no report yet
  double last_altitude_ = -1;  // the last report's, as the DVL gave it
  int last_status_ = 0;
  unsigned said_ = 0;
  std::int64_t *velocity_, *dead_reckoning_, *ignored_, *malformed_, *invalid_, *bad_velocity_;
  std::int64_t *fom_high_, *lock_lost_, *lock_regained_, *connects_, *disconnects_, *overlong_;
};

}  // namespace tiller::sensors
