// tiller-navigator's logic: the Blue Robotics Navigator's ICM-20602 (SPI) and AK09915 (I2C; or the
// MMC5983MA of newer boards, `compass: mmc5983`, sensors/mmc5983.hpp)
// through the AHRS (ahrs/mahony.hpp) -> imu_t on TILLER_IMU (body FRD rates in rad/s, specific
// force in m/s^2, orientation body -> NED) and heading_t on TILLER_HEADING (SOURCE_AHRS), one
// sample a tick at rate_hz.
//
// A tick: one 15-byte ICM-20602 burst (skipped, "imu.not_ready", when DATA_RDY is clear), one
// 9-byte AK09915 read (used when DRDY is set and not overflowed), both turned into the body frame
// by their `mount`, the field corrected by the vehicle's compass calibration
// (ahrs/compass_calibration.hpp), one AHRS step with dt from the tick times, the declination
// added. orientation_valid (and heading_t) need the compass up, the filter aligned, and
// settle_s since the alignment. Device health as tiller-imu's (sensors/device_health.hpp): one
// retry, then "bus.errors"; fault_after failed ticks or a failed set-up: the device is down, set
// up again every retry period (the ICM-20602's set-up waits its 100 ms reset: that tick is late
// once). IMU down: FAULT; compass down: DEGRADED, rates and specific force still published,
// orientation not valid. Time comes only from the executor; no allocation in a steady tick.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <tiller/heading_t.hpp>
#include <tiller/imu_t.hpp>

#include "ahrs/compass_calibration.hpp"
#include "ahrs/mahony.hpp"
#include "i2c/transport.hpp"
#include "runtime/node.hpp"
#include "sensors/ak09915.hpp"
#include "sensors/bno055.hpp"
#include "sensors/device_health.hpp"
#include "sensors/icm20602.hpp"
#include "sensors/mmc5983.hpp"
#include "spi/transport.hpp"

namespace tiller::config {
class Value;
}

namespace tiller::sensors {

struct NavigatorParams {
  std::string spi = "/dev/spidev1.0";
  std::uint32_t spi_speed_hz = 1'000'000;
  std::string i2c = "/dev/i2c-1";
  bool compass_mmc5983 = false;  // `compass: mmc5983` (newer boards) instead of the AK09915
  std::uint8_t compass_address = ak09915::kAddress;  // the MMC5983's default: 0x30
  double rate_hz = 100;                              // 10..200, a divisor of the ICM-20602's 1 kHz
  icm20602::Config imu;
  bno055::Mount mount;          // ICM-20602 chip axes -> body FRD
  bno055::Mount compass_mount;  // AK09915 chip axes -> body FRD
  ahrs::CompassCalibration compass_calibration;
  ahrs::MahonyParams filter;
  double declination = 0;  // rad, east positive
  bool true_north = false;
  double settle_s = 2.0;
  double angular_rate_std = 0, specific_force_std = 0, orientation_std = 0, heading_std = 0;
  std::string imu_channel = "TILLER_IMU";
  std::string heading_channel = "TILLER_HEADING";
  TimeUs retry_period = kUsPerSecond;
  int fault_after = 5;
};

NavigatorParams load_navigator_params(const config::Value& root);
NavigatorParams load_navigator_file(const std::string& path);

class NavigatorNode : public Node {
 public:
  NavigatorNode(const NavigatorParams& p, spi::Transport& spi, i2c::Transport& i2c);
  bool imu_up() const { return imu_up_; }
  bool compass_up() const { return compass_up_; }
  const ahrs::Mahony& filter() const { return ahrs_; }
  // Compass recording (tiller-navigator --calibrate-compass): from now on keep every good
  // compass sample in body axes before the calibration (uT), up to `max_samples` (reserved here,
  // so the ticks still allocate nothing); recorded() is what ahrs::fit_ellipsoid takes.
  void record_compass(std::size_t max_samples);
  const std::vector<std::array<double, 3>>& recorded() const { return recorded_; }

 protected:
  void on_tick(TimeUs now) override;

 private:
  void set_up(TimeUs now);
  bool read_compass(TimeUs now, ahrs::Vec3& field);
  void publish_sample(TimeUs now, const icm20602::Sample& s, const ahrs::Vec3* field);
  void update_health(TimeUs now);

  NavigatorParams p_;
  spi::Transport& spi_;
  i2c::Transport& i2c_;
  icm20602::Device imu_dev_;
  ak09915::Device compass_dev_;
  mmc5983::Device mmc_dev_;
  DeviceHealth imu_health_, compass_health_;
  bool imu_up_ = false, compass_up_ = false;
  ahrs::Mahony ahrs_;
  TimeUs last_sample_ = INT64_MIN, aligned_at_ = INT64_MIN;
  icm20602::Burst burst_{};
  ak09915::Burst mag_burst_{};
  mmc5983::Burst mmc_burst_{};
  imu_t imu_{};
  heading_t heading_{};
  std::int64_t *retries_, *bus_errors_, *init_failures_, *not_ready_, *mag_overflow_, *samples_,
      *headings_, *rejected_imu_, *rejected_heading_;
  std::string status_;
  int health_key_ = -1;
  bool recording_ = false;
  std::vector<std::array<double, 3>> recorded_;
};

}  // namespace tiller::sensors
