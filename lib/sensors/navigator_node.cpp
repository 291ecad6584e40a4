#include "sensors/navigator_node.hpp"

#include <cerrno>
#include <cmath>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "sensors/imu_node.hpp"

namespace tiller::sensors {

namespace {
ahrs::Vec3 to_body(const bno055::Mount& m, const double chip[3]) {
  return {m.sign[0] * chip[m.axis[0]], m.sign[1] * chip[m.axis[1]], m.sign[2] * chip[m.axis[2]]};
}
void diagonal(double* cov, double std) {
  for (int i = 0; i < 9; ++i) cov[i] = 0;
  for (int i = 0; i < 3; ++i) cov[4 * i] = std * std;
}
}  // namespace

NavigatorParams load_navigator_params(const config::Value& root) {
  NavigatorParams p;
  p.spi = root.string_or("spi", p.spi);
  p.spi_speed_hz = static_cast<std::uint32_t>(
      root.integer_or("spi_speed_hz", p.spi_speed_hz, 100'000, 10'000'000));
  p.i2c = root.string_or("i2c", p.i2c);
  p.compass_mmc5983 = root.choice_or("compass", "ak09915", {"ak09915", "mmc5983"}) == "mmc5983";
  if (p.compass_mmc5983) {
    p.compass_address = static_cast<std::uint8_t>(
        root.integer_or("compass_address", mmc5983::kAddress, 0x30, 0x30));
  } else {
    p.compass_address = static_cast<std::uint8_t>(
        root.integer_or("compass_address", p.compass_address, 0x0C, 0x0F));
  }
  const auto rate = root.integer_or("rate_hz", 100, 10, 200);
  if (1000 % rate != 0) root.at("rate_hz").fail("a divisor of 1000 in 10..200 (e.g. 50, 100, 200)");
  p.rate_hz = static_cast<double>(rate);
  p.imu.sample_rate_div = static_cast<std::uint8_t>(1000 / rate - 1);
  const auto g = root.choice_or("gyro_range_dps", "1000", {"250", "500", "1000", "2000"});
  p.imu.gyro_range = static_cast<icm20602::GyroRange>(g == "250"    ? 0
                                                      : g == "500"  ? 1
                                                      : g == "1000" ? 2
                                                                    : 3);
  const auto a = root.choice_or("accel_range_g", "8", {"2", "4", "8", "16"});
  p.imu.accel_range = static_cast<icm20602::AccelRange>(a == "2"   ? 0
                                                        : a == "4" ? 1
                                                        : a == "8" ? 2
                                                                   : 3);
  if (const auto m = root.find("mount")) p.mount = load_mount(*m);
  p.compass_mount = p.mount;
  if (const auto m = root.find("compass_mount")) p.compass_mount = load_mount(*m);
  if (const auto c = root.find("compass_calibration")) {
    const auto o = c->numbers("offset_ut", 3);
    const auto s = c->numbers("matrix", 9);
    for (int i = 0; i < 3; ++i) p.compass_calibration.offset[i] = o[i];
    for (int i = 0; i < 9; ++i) p.compass_calibration.matrix[i] = s[i];
    p.filter.mag_norm = c->number_or("field_ut", 0.0, {0, 100});
  }
  if (root.has("declination_deg")) {
    p.true_north = true;
    p.declination = root.angle_deg("declination_deg", {-180, 180});
  }
  p.filter.kp = root.number_or("kp", p.filter.kp, {0.01, 20});
  p.filter.ki = root.number_or("ki", p.filter.ki, {0, 5});
  p.settle_s = root.number_or("settle_s", p.settle_s, {0, 60});
  p.angular_rate_std = root.angle_deg_or("angular_rate_std_deg", 0, config::Range::at_least(0));
  p.specific_force_std = root.number_or("specific_force_std", 0, config::Range::at_least(0));
  p.orientation_std = root.angle_deg_or("orientation_std_deg", 0, {0, 90});
  p.heading_std = root.angle_deg_or("heading_std_deg", 0, {0, 180});
  p.imu_channel = root.string_or("imu_channel", p.imu_channel);
  p.heading_channel = root.string_or("heading_channel", p.heading_channel);
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  p.fault_after = static_cast<int>(root.integer_or("fault_after", p.fault_after, 1, 1000));
  root.check_all_used();
  return p;
}

NavigatorParams load_navigator_file(const std::string& path) {
  return load_navigator_params(config::Value::load_file(path));
}

NavigatorNode::NavigatorNode(const NavigatorParams& p, spi::Transport& spi, i2c::Transport& i2c)
    : Node("navigator", from_hz(p.rate_hz)),
      p_(p),
      spi_(spi),
      i2c_(i2c),
      imu_dev_(spi, p.imu),
      compass_dev_(i2c, p.compass_address, static_cast<int>(p.rate_hz) >= 100 ? 100 : 50),
      mmc_dev_(i2c, p.compass_address, static_cast<int>(p.rate_hz) >= 100 ? 100 : 50),
      imu_health_("icm20602 on " + spi.name(), p.retry_period, p.fault_after),
      compass_health_(std::string(p.compass_mmc5983 ? "mmc5983" : "ak09915") + " on " + i2c.name() +
                          " at " + hex(p.compass_address),
                      p.retry_period, p.fault_after),
      ahrs_(p.filter) {
  advertise<imu_t>(p.imu_channel);
  advertise<heading_t>(p.heading_channel);
  retries_ = &counter("bus.retries");
  bus_errors_ = &counter("bus.errors");
  init_failures_ = &counter("init.failures");
  not_ready_ = &counter("imu.not_ready");
  mag_overflow_ = &counter("compass.overflow");
  samples_ = &counter("samples");
  headings_ = &counter("headings");
  rejected_imu_ = &counter("rejected.imu.range");
  rejected_heading_ = &counter("rejected.heading.range");
  diagonal(imu_.angular_rate_covariance, p.angular_rate_std);
  diagonal(imu_.specific_force_covariance, p.specific_force_std);
  diagonal(imu_.orientation_covariance, p.orientation_std);
  imu_.heading_is_magnetic = !p.true_north;
  imu_.calibration_system = imu_.calibration_gyro = imu_.calibration_accel = imu_.calibration_mag =
      -1;
  heading_.variance = p.heading_std * p.heading_std;
  heading_.reference = p.true_north ? heading_t::REFERENCE_TRUE : heading_t::REFERENCE_MAGNETIC;
  heading_.source = heading_t::SOURCE_AHRS;
  heading_.device = "navigator@" + spi.name() + "," + i2c.name() + ":" + hex(p.compass_address);
  set_health(heartbeat_t::STATE_FAULT, imu_health_.where() + ": not set up yet");
}

void NavigatorNode::set_up(TimeUs now) {
  if (!imu_up_ && imu_health_.may_try(now)) {
    const int err = imu_dev_.start();
    imu_up_ = err == 0;
    if (!imu_up_) {
      ++*init_failures_;
      const std::string why = err == EPROTO ? "WHO_AM_I reads " + hex(imu_dev_.who_am_i()) +
                                                  ", not 0x12 (another chip on this chip select)"
                                            : "no answer (is SPI enabled, the right chip select?)";
      status_ = imu_health_.down(now, err == EPROTO ? 0 : err, why);
      health_key_ = -1;
      set_health(heartbeat_t::STATE_FAULT, status_);
    }
  }
  if (!compass_up_ && compass_health_.may_try(now)) {
    const int err = p_.compass_mmc5983 ? mmc_dev_.start() : compass_dev_.start();
    compass_up_ = err == 0;
    if (!compass_up_) {
      ++*init_failures_;
      const std::string wrong =
          p_.compass_mmc5983 ? "product id reads " + hex(mmc_dev_.product_id()) + ", not 0x30"
                             : "WIA reads " + hex(compass_dev_.wia(), 4) + ", not 0x4810";
      compass_health_.down(now, err == EPROTO ? 0 : err, err == EPROTO ? wrong : "no answer");
    }
  }
}

bool NavigatorNode::read_compass(TimeUs now, ahrs::Vec3& field) {
  if (!compass_up_) return false;
  const int err = retry_once(*retries_, [&] {
    return p_.compass_mmc5983 ? mmc_dev_.read(mmc_burst_) : compass_dev_.read(mag_burst_);
  });
  if (err != 0) {
    ++*bus_errors_;
    if (compass_health_.failed(now)) {
      compass_up_ = false;
      compass_health_.down(now, err, "reads failed in a row");
    }
    return false;
  }
  compass_health_.succeeded();
  double chip[3];
  if (p_.compass_mmc5983) {
    const mmc5983::Sample m = mmc5983::convert(mmc_burst_);
    if (!m.data_ready) return false;
    for (int i = 0; i < 3; ++i) chip[i] = m.field_ut[i];
  } else {
    const ak09915::Sample m = ak09915::convert(mag_burst_);
    if (!m.data_ready) return false;
    if (m.overflow) {
      ++*mag_overflow_;
      return false;
    }
    for (int i = 0; i < 3; ++i) chip[i] = m.field_ut[i];
  }
  const ahrs::Vec3 body = to_body(p_.compass_mount, chip);
  if (recording_ && recorded_.size() < recorded_.capacity())
    recorded_.push_back({body[0], body[1], body[2]});
  field = p_.compass_calibration.apply(body);
  return true;
}

void NavigatorNode::record_compass(std::size_t max_samples) {
  recorded_.clear();
  recorded_.reserve(max_samples);
  recording_ = true;
}

void NavigatorNode::on_tick(TimeUs now) {
  spi_.set_time(now);
  i2c_.set_time(now);
  set_up(now);
  if (!imu_up_) return;
  const int err = retry_once(*retries_, [&] { return imu_dev_.read(burst_); });
  if (err != 0) {
    ++*bus_errors_;
    if (imu_health_.failed(now)) {
      imu_up_ = false;
      status_ = imu_health_.down(now, err, "reads failed in a row");
      health_key_ = -1;
      set_health(heartbeat_t::STATE_FAULT, status_);
    }
    return;
  }
  imu_health_.succeeded();
  const icm20602::Sample s = icm20602::convert(burst_, p_.imu);
  if (!s.data_ready) {
    ++*not_ready_;
    return;
  }
  ahrs::Vec3 field{};
  const bool have_field = read_compass(now, field);
  publish_sample(now, s, have_field ? &field : nullptr);
  update_health(now);
}

void NavigatorNode::publish_sample(TimeUs now, const icm20602::Sample& s, const ahrs::Vec3* field) {
  const ahrs::Vec3 gyro = to_body(p_.mount, s.gyro), acc = to_body(p_.mount, s.accel);
  const bool was_aligned = ahrs_.aligned();
  const double dt = last_sample_ == INT64_MIN ? 0.0 : to_seconds(now - last_sample_);
  last_sample_ = now;
  if (dt > 0 || !was_aligned) ahrs_.update(gyro, acc, field, dt > 0 ? dt : 1.0);
  if (ahrs_.aligned() && !was_aligned) aligned_at_ = now;
  const ahrs::Quat qd{std::cos(p_.declination / 2), 0, 0, std::sin(p_.declination / 2)};
  const ahrs::Quat q = ahrs::multiply(qd, ahrs_.q());
  imu_.utime = now;
  for (int i = 0; i < 3; ++i) {
    imu_.angular_rate[i] = gyro[i];
    imu_.specific_force[i] = acc[i];
  }
  for (int i = 0; i < 4; ++i) imu_.orientation[i] = q[i];
  imu_.orientation_valid =
      compass_up_ && ahrs_.aligned() && now - aligned_at_ >= from_seconds(p_.settle_s);
  imu_.temperature = s.temperature_c;
  if (checks::check(imu_) != nullptr) {
    reject(*rejected_imu_);
    return;
  }
  ++*samples_;
  publish(p_.imu_channel, imu_);
  if (!imu_.orientation_valid) return;
  heading_.utime = now;
  heading_.heading = ahrs::euler_of(q)[2];
  if (checks::check(heading_) != nullptr) {
    reject(*rejected_heading_);
    return;
  }
  ++*headings_;
  publish(p_.heading_channel, heading_);
}

void NavigatorNode::update_health(TimeUs now) {
  int key = 0;
  if (imu_health_.failed_recently(now))
    key = 1;
  else if (!compass_up_)
    key = 2;
  else if (!imu_.orientation_valid)
    key = 3;
  if (key == health_key_) {
    set_health(key == 0 ? heartbeat_t::STATE_OK : heartbeat_t::STATE_DEGRADED, status_);
    return;
  }
  health_key_ = key;
  switch (key) {
    case 1:
      status_ = imu_health_.where() + ": bus errors in the last second";
      break;
    case 2:
      status_ = compass_health_.where() + " down: no heading; retrying";
      break;
    case 3:
      status_ = imu_health_.where() + ": AHRS settling, orientation not valid yet";
      break;
    default:
      status_ = imu_health_.where() + ", " + compass_health_.where();
  }
  set_health(key == 0 ? heartbeat_t::STATE_OK : heartbeat_t::STATE_DEGRADED, status_);
}

}  // namespace tiller::sensors
