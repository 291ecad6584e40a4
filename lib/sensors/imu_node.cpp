#include "sensors/imu_node.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>

#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

namespace {

// "+x", "-y", "z" -> axis and sign.
void parse_axis(const config::Value& v, int& axis, int& sign) {
  const std::string s = v.as_string();
  const std::string expected = "one of +x, -x, +y, -y, +z, -z (the chip axis along it)";
  std::size_t i = 0;
  sign = +1;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) {
    sign = s[0] == '-' ? -1 : +1;
    i = 1;
  }
  if (s.size() != i + 1 || s[i] < 'x' || s[i] > 'z') v.fail(expected);
  axis = s[i] - 'x';
}

void diagonal(double* cov, double std) {
  for (int i = 0; i < 9; ++i) cov[i] = 0;
  for (int i = 0; i < 3; ++i) cov[4 * i] = std * std;
}
}  // namespace

bno055::Mount load_mount(const config::Value& m) {
  bno055::Mount mount;
  const char* keys[3] = {"forward", "right", "down"};
  for (int i = 0; i < 3; ++i) {
    if (const auto a = m.find(keys[i])) parse_axis(*a, mount.axis[i], mount.sign[i]);
  }
  if (!bno055::is_rotation(mount)) {
    m.fail(
        "forward, right and down along three different chip axes forming a right-handed "
        "frame (e.g. forward: +y, right: +x, down: -z)");
  }
  return mount;
}

ImuParams load_imu_params(const config::Value& root) {
  ImuParams p;
  p.bus = root.string_or("bus", p.bus);
  p.address = static_cast<std::uint8_t>(root.integer_or("address", p.address, 0x28, 0x29));
  p.mode = root.choice_or("mode", "ndof", {"ndof", "ndof_fmc_off"}) == "ndof"
               ? bno055::kModeNdof
               : bno055::kModeNdofFmcOff;
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {1, 100});
  if (const auto m = root.find("mount")) p.mount = load_mount(*m);
  if (root.has("declination_deg")) {
    p.true_north = true;
    p.declination = root.angle_deg("declination_deg", {-180, 180});
  }
  p.min_system_calibration =
      static_cast<int>(root.integer_or("min_system_calibration", p.min_system_calibration, 0, 3));
  p.angular_rate_std = root.angle_deg_or("angular_rate_std_deg", 0, config::Range::at_least(0));
  p.specific_force_std = root.number_or("specific_force_std", 0, config::Range::at_least(0));
  p.orientation_std = root.angle_deg_or("orientation_std_deg", 0, {0, 90});
  p.heading_std = root.angle_deg_or("heading_std_deg", 0, {0, 180});
  p.imu_channel = root.string_or("imu_channel", p.imu_channel);
  p.heading_channel = root.string_or("heading_channel", p.heading_channel);
  p.publish_heading = root.boolean_or("publish_heading", p.publish_heading);
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  p.fault_after = static_cast<int>(root.integer_or("fault_after", p.fault_after, 1, 1000));
  root.check_all_used();
  return p;
}

ImuParams load_imu_file(const std::string& path) {
  return load_imu_params(config::Value::load_file(path));
}

ImuNode::ImuNode(const ImuParams& p, i2c::Transport& bus)
    : Node("imu", from_hz(p.rate_hz)),
      p_(p),
      bus_(bus),
      health_("bno055 on " + bus.name() + " at " + hex(p.address), p.retry_period, p.fault_after) {
  advertise<imu_t>(p.imu_channel);
  if (p.publish_heading) advertise<heading_t>(p.heading_channel);
  retries_ = &counter("bus.retries");
  bus_errors_ = &counter("bus.errors");
  init_failures_ = &counter("init.failures");
  resets_ = &counter("device.resets");
  device_errors_ = &counter("device.errors");
  not_fusing_ = &counter("fusion.not_running");
  uncalibrated_ = &counter("orientation.uncalibrated");
  samples_ = &counter("samples");
  headings_ = &counter("headings");
  rejected_imu_ = &counter("rejected.imu.range");
  rejected_heading_ = &counter("rejected.heading.range");
  diagonal(imu_.angular_rate_covariance, p.angular_rate_std);
  diagonal(imu_.specific_force_covariance, p.specific_force_std);
  diagonal(imu_.orientation_covariance, p.orientation_std);
  imu_.heading_is_magnetic = !p.true_north;
  heading_.variance = p.heading_std * p.heading_std;
  heading_.reference = p.true_north ? heading_t::REFERENCE_TRUE : heading_t::REFERENCE_MAGNETIC;
  heading_.source = heading_t::SOURCE_AHRS;
  heading_.device = "bno055@" + bus.name() + ":" + hex(p.address);
  set_health(heartbeat_t::STATE_FAULT, health_.where() + ": not set up yet");
}

int ImuNode::write_reg(std::uint8_t reg, std::uint8_t value) {
  const std::uint8_t b[2] = {reg, value};
  return bus_.write(p_.address, b, 2);
}

int ImuNode::with_retry(auto&& op) {
  return retry_once(*retries_, op);
}

void ImuNode::lost(TimeUs now, int err, std::string_view why) {
  state_ = State::down;
  status_ = health_.down(now, err, why);
  next_step_ = health_.next_try();
  health_key_ = 0;
  set_health(heartbeat_t::STATE_FAULT, status_);
}

void ImuNode::set_up(TimeUs now) {
  if (now < next_step_) return;
  if (state_ == State::down) {
    std::uint8_t id = 0;
    int err =
        with_retry([&] { return bus_.write_read(p_.address, &bno055::kRegChipId, 1, &id, 1); });
    if (err == 0 && id != bno055::kChipIdValue) {
      ++*init_failures_;
      lost(now, 0,
           "CHIP_ID reads " + hex(id) + ", not 0xa0 (another chip at that address, or a " +
               "BNO055 still booting: 650 ms after power-on)");
      return;
    }
    if (err == 0)
      err = with_retry([&] { return write_reg(bno055::kRegOprMode, bno055::kModeConfig); });
    if (err != 0) {
      ++*init_failures_;
      lost(now, err, "no answer (is it wired, powered, at that address?)");
      return;
    }
    state_ = State::configuring;
    next_step_ = now + bno055::kToConfigUs;
    return;
  }
  if (state_ == State::configuring) {
    int err = 0;
    const std::uint8_t writes[4][2] = {{bno055::kRegPageId, 0},
                                       {bno055::kRegPwrMode, bno055::kPwrNormal},
                                       {bno055::kRegUnitSel, bno055::kUnitSel},
                                       {bno055::kRegOprMode, p_.mode}};
    for (const auto& w : writes) {
      if (err == 0) err = with_retry([&] { return write_reg(w[0], w[1]); });
    }
    if (err != 0) {
      ++*init_failures_;
      lost(now, err, "set-up write failed");
      return;
    }
    state_ = State::starting;
    next_step_ = now + bno055::kFromConfigUs;
    return;
  }
  state_ = State::running;  // starting, and the mode switch time has passed
  health_.succeeded();
}

void ImuNode::on_tick(TimeUs now) {
  bus_.set_time(now);
  if (state_ != State::running) {
    set_up(now);
    if (state_ != State::running) return;
  }
  sample(now);
}

void ImuNode::sample(TimeUs now) {
  const int err = with_retry([&] {
    return bus_.write_read(p_.address, &bno055::kRegAccData, 1, burst_.data(), burst_.size());
  });
  if (err != 0) {
    ++*bus_errors_;
    if (health_.failed(now)) {
      lost(now, err, std::to_string(health_.consecutive()) + " reads failed in a row");
    } else {
      update_health(now, nullptr);
    }
    return;
  }
  health_.succeeded();
  const bno055::Raw raw = bno055::decode(burst_);
  if (raw.opr_mode != p_.mode || raw.unit_sel != bno055::kUnitSel) {
    ++*resets_;
    health_.glitch(now);
    state_ = State::down;  // the chip reset itself (brown-out?): set it up again now
    next_step_ = now;
    status_ = health_.where() + ": the chip reset itself (OPR_MODE " + hex(raw.opr_mode) +
              ", UNIT_SEL " + hex(raw.unit_sel) + "); setting it up again";
    health_key_ = 0;
    set_health(heartbeat_t::STATE_DEGRADED, status_);
    return;
  }
  if (raw.sys_status == bno055::kSysStatusError) {
    ++*device_errors_;
    lost(now, 0,
         std::string("system error: ") + bno055::sys_error_text(raw.sys_err) + " (SYS_ERR " +
             hex(raw.sys_err) + ")");
    return;
  }
  if (raw.sys_status != bno055::kSysStatusFusionRunning) {
    ++*not_fusing_;
    update_health(now, &raw);
    return;
  }
  const double yaw = bno055::convert(raw, p_.mount, p_.declination, imu_);
  if (imu_.orientation_valid && imu_.calibration_system < p_.min_system_calibration) {
    imu_.orientation_valid = false;
    ++*uncalibrated_;
  }
  imu_.utime = now;
  if (checks::check(imu_) != nullptr) {
    reject(*rejected_imu_);
  } else {
    ++*samples_;
    publish(p_.imu_channel, imu_);
    if (p_.publish_heading && imu_.orientation_valid) {
      heading_.utime = now;
      heading_.heading = yaw;
      if (checks::check(heading_) != nullptr) {
        reject(*rejected_heading_);
      } else {
        ++*headings_;
        publish(p_.heading_channel, heading_);
      }
    }
  }
  update_health(now, &raw);
}

void ImuNode::say(std::int8_t state, int key, auto&& make) {
  if (key != health_key_) {  // built only when it changes: a steady state allocates nothing
    health_key_ = key;
    status_ = make();
  }
  set_health(state, status_);
}

void ImuNode::update_health(TimeUs now, const bno055::Raw* raw) {
  if (health_.failed_recently(now)) {
    say(heartbeat_t::STATE_DEGRADED, 1,
        [&] { return health_.where() + ": bus errors in the last second"; });
    return;
  }
  if (raw == nullptr) return;
  if (raw->sys_status != bno055::kSysStatusFusionRunning) {
    say(heartbeat_t::STATE_DEGRADED, 0x200 | raw->sys_status, [&] {
      return health_.where() + ": fusion not running (SYS_STATUS " + hex(raw->sys_status) + ")";
    });
    return;
  }
  const auto c = bno055::calibration(raw->calib_stat);
  if (c.system < p_.min_system_calibration) {
    say(heartbeat_t::STATE_DEGRADED, 0x300 | raw->calib_stat, [&] {
      return health_.where() + ": calibrating, orientation not valid yet (system " +
             std::to_string(c.system) + " < " + std::to_string(p_.min_system_calibration) +
             "; gyro " + std::to_string(c.gyro) + ", accel " + std::to_string(c.accel) + ", mag " +
             std::to_string(c.mag) + ")";
    });
    return;
  }
  say(heartbeat_t::STATE_OK, 0x400, [&] { return health_.where(); });
}

}  // namespace tiller::sensors
