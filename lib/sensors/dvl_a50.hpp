// The Water Linked DVL-A50's TCP JSON protocol (json_v3 / json_v3.1; docs.waterlinked.com,
// "DVL protocol", JSON protocol (TCP), port 16171): one JSON object per line. Two reports are
// read:
//   "type": "velocity"        vx vy vz (m/s, the DVL's frame: x forward, y right, z down for
//                             the default mounting; the DVL applies its configured mounting
//                             rotation), fom (figure of merit, m/s: the velocity's accuracy),
//                             covariance (3x3, (m/s)^2; json_v3 on), altitude (m, the distance to
//                             the bottom; negative: none), velocity_valid (bottom lock), status
//                             (0 normal), time (ms since the previous velocity report),
//                             time_of_validity (us, the DVL's clock: the ping's centre),
//                             transducers[] (beam_valid each);
//   "type": "position_local"  the DVL's own dead reckoning: ts (s), x y z (m, from where it was
//                             reset), std (m), roll pitch yaw (deg in the protocol; rad here),
//                             status.
// Other types (command responses, "imu") are ignored and counted as such. A line that is not a
// JSON object, lacks a required field, has a field of the wrong type or a value out of range (a
// non-finite number, |v| > 20 m/s, fom < 0, a covariance that is not 3x3) is refused with the
// reason; the caller counts it and keeps going. No state: the same line, the same result.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace tiller::sensors {

struct DvlVelocity {
  std::array<double, 3> velocity{};  // m/s, DVL frame
  double fom = 0;                    // m/s
  bool has_covariance = false;
  std::array<double, 9> covariance{};     // (m/s)^2, row-major
  double altitude = -1;                   // m; < 0: no bottom distance
  bool bottom_lock = false;               // velocity_valid
  int status = 0;                         // 0: normal
  double dt_s = 0;                        // since the previous velocity report
  std::int64_t time_of_validity_us = -1;  // DVL clock; -1: not given (json_v2)
  int beams_valid = -1;                   // of the transducers; -1: not given
};

struct DvlDeadReckoning {
  double ts_s = 0;
  std::array<double, 3> position{};  // m
  double std_m = 0;
  std::array<double, 3> attitude{};  // roll, pitch, yaw, rad
  int status = 0;
};

enum class DvlLine { kVelocity, kDeadReckoning, kIgnored, kMalformed, kInvalid };

struct DvlParsed {
  DvlLine kind = DvlLine::kMalformed;
  DvlVelocity velocity;             // kind kVelocity
  DvlDeadReckoning dead_reckoning;  // kind kDeadReckoning
  std::string why;                  // kMalformed, kInvalid: what is wrong; kIgnored: the type
};

DvlParsed parse_dvl_line(std::string_view line);

// A velocity the estimator may use: bottom lock, status 0, fom at most `max_fom` (m/s).
bool dvl_velocity_usable(const DvlVelocity& v, double max_fom);

}  // namespace tiller::sensors
