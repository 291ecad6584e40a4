#include "sensors/bno055.hpp"

#include <cmath>

namespace tiller::sensors::bno055 {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

std::int16_t le16(const Burst& b, std::uint8_t reg) {
  const std::size_t i = reg - kRegAccData;
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(b[i]) |
                                   static_cast<std::uint16_t>(b[i + 1] << 8));
}
std::uint8_t u8(const Burst& b, std::uint8_t reg) {
  return b[reg - kRegAccData];
}
void vec3(const Burst& b, std::uint8_t reg, std::array<std::int16_t, 3>& v) {
  for (std::uint8_t i = 0; i < 3; ++i) v[i] = le16(b, static_cast<std::uint8_t>(reg + 2 * i));
}
double wrap_pi(double a) {
  a = std::remainder(a, 2 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2 * kPi : a;
}
}  // namespace

Raw decode(const Burst& b) {
  Raw r;
  vec3(b, 0x08, r.acc);
  vec3(b, 0x0E, r.mag);
  vec3(b, 0x14, r.gyr);
  vec3(b, kRegEulData, r.eul);
  for (std::uint8_t i = 0; i < 4; ++i) r.qua[i] = le16(b, static_cast<std::uint8_t>(0x20 + 2 * i));
  vec3(b, 0x28, r.lia);
  vec3(b, 0x2E, r.grv);
  r.temp = static_cast<std::int8_t>(u8(b, kRegTemp));
  r.calib_stat = u8(b, kRegCalibStat);
  r.sys_status = u8(b, kRegSysStatus);
  r.sys_err = u8(b, kRegSysErr);
  r.unit_sel = u8(b, kRegUnitSel);
  r.opr_mode = u8(b, kRegOprMode);
  return r;
}

bool is_rotation(const Mount& m) {
  double c[3][3] = {};  // columns: body axes in chip coordinates
  for (int i = 0; i < 3; ++i) {
    if (m.axis[i] < 0 || m.axis[i] > 2 || (m.sign[i] != 1 && m.sign[i] != -1)) return false;
    c[m.axis[i]][i] = m.sign[i];
  }
  const double det = c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) -
                     c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
                     c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
  return det == 1.0;  // also 0 when an axis is used twice
}

Calibration calibration(std::uint8_t s) {
  return {static_cast<std::int8_t>((s >> 6) & 3), static_cast<std::int8_t>((s >> 4) & 3),
          static_cast<std::int8_t>((s >> 2) & 3), static_cast<std::int8_t>(s & 3)};
}

double convert(const Raw& raw, const Mount& mount, double declination_rad, imu_t& out) {
  for (int i = 0; i < 3; ++i) {
    const int a = mount.axis[i];
    out.angular_rate[i] = mount.sign[i] * raw.gyr[a] / kGyrLsbPerDps * kDegToRad;
    out.specific_force[i] = mount.sign[i] * raw.acc[a] / kAccLsbPerMs2;
  }
  // R_enu_chip from the quaternion (chip -> east-north-up).
  const double w = raw.qua[0] / kQuaLsb, x = raw.qua[1] / kQuaLsb, y = raw.qua[2] / kQuaLsb,
               z = raw.qua[3] / kQuaLsb;
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  // R_ned_body = Rz(declination) * R_ned_enu * R_enu_chip * R_chip_body. R_ned_enu swaps the
  // first two rows and negates the third; R_chip_body's column i is sign_i * e_axis_i.
  double n[3][3];
  for (int i = 0; i < 3; ++i) {
    const int a = mount.axis[i];
    n[0][i] = mount.sign[i] * r[1][a];
    n[1][i] = mount.sign[i] * r[0][a];
    n[2][i] = -mount.sign[i] * r[2][a];
  }
  const double cd = std::cos(declination_rad), sd = std::sin(declination_rad);
  for (int i = 0; i < 3; ++i) {
    const double a = n[0][i], b = n[1][i];
    n[0][i] = cd * a - sd * b;
    n[1][i] = sd * a + cd * b;
  }
  // Rotation matrix -> quaternion [w x y z], w >= 0 (Shepperd's method, the largest pivot).
  double q[4];
  const double tr = n[0][0] + n[1][1] + n[2][2];
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    q[0] = s / 4;
    q[1] = (n[2][1] - n[1][2]) / s;
    q[2] = (n[0][2] - n[2][0]) / s;
    q[3] = (n[1][0] - n[0][1]) / s;
  } else if (n[0][0] > n[1][1] && n[0][0] > n[2][2]) {
    const double s = 2 * std::sqrt(1 + n[0][0] - n[1][1] - n[2][2]);
    q[0] = (n[2][1] - n[1][2]) / s;
    q[1] = s / 4;
    q[2] = (n[0][1] + n[1][0]) / s;
    q[3] = (n[0][2] + n[2][0]) / s;
  } else if (n[1][1] > n[2][2]) {
    const double s = 2 * std::sqrt(1 + n[1][1] - n[0][0] - n[2][2]);
    q[0] = (n[0][2] - n[2][0]) / s;
    q[1] = (n[0][1] + n[1][0]) / s;
    q[2] = s / 4;
    q[3] = (n[1][2] + n[2][1]) / s;
  } else {
    const double s = 2 * std::sqrt(1 + n[2][2] - n[0][0] - n[1][1]);
    q[0] = (n[1][0] - n[0][1]) / s;
    q[1] = (n[0][2] + n[2][0]) / s;
    q[2] = (n[1][2] + n[2][1]) / s;
    q[3] = s / 4;
  }
  const double sign = q[0] < 0 ? -1.0 : 1.0;
  // The matrix is built from the unnormalised quaternion; scale back to its norm so that a
  // bad reading (e.g. all zeros while the fusion starts) keeps its bad norm.
  for (int i = 0; i < 4; ++i) out.orientation[i] = std::isfinite(q[i]) ? sign * q[i] * norm : 0.0;
  out.orientation_valid = raw.sys_status == kSysStatusFusionRunning && norm >= 0.99 && norm <= 1.01;
  const Calibration c = calibration(raw.calib_stat);
  out.calibration_system = c.system;
  out.calibration_gyro = c.gyro;
  out.calibration_accel = c.accel;
  out.calibration_mag = c.mag;
  out.temperature = raw.temp;
  return wrap_pi(std::atan2(n[1][0], n[0][0]));
}

double euler_heading_rad(const Raw& raw) {
  return wrap_pi(raw.eul[0] / kEulLsbPerDeg * kDegToRad);
}

const char* sys_error_text(std::uint8_t e) {
  switch (e) {
    case 0:
      return "no error";
    case 1:
      return "peripheral initialization error";
    case 2:
      return "system initialization error";
    case 3:
      return "self test failed";
    case 4:
      return "register map value out of range";
    case 5:
      return "register map address out of range";
    case 6:
      return "register map write error";
    case 7:
      return "low power mode not available for the operation mode";
    case 8:
      return "accelerometer power mode not available";
    case 9:
      return "fusion algorithm configuration error";
    case 10:
      return "sensor configuration error";
    default:
      return "unknown error code";
  }
}

}  // namespace tiller::sensors::bno055
