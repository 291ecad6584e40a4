#include "sensors/power_node.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>

#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

PowerParams load_power_params(const config::Value& root) {
  PowerParams p;
  if (root.string_or("device", "ina226") != "ina226") root.at("device").fail("ina226 or ads1115");
  p.bus = root.string_or("bus", p.bus);
  p.address = static_cast<std::uint8_t>(root.integer_or("address", p.address, 0x40, 0x4F));
  p.shunt_ohm = root.number("shunt_ohm", {1e-5, 10});
  const double max_current = root.number("max_current_a", {0.001, 1000});
  // Data sheet equation 2: the finest LSB for the largest expected current.
  p.current_lsb = root.number_or("current_lsb_a", max_current / 32768.0, {1e-7, 1});
  if (p.current_lsb * 32768 < max_current) {
    root.at("current_lsb_a")
        .fail("an LSB of at least max_current_a / 2^15 = " + std::to_string(max_current / 32768) +
              " A (the current register is 16-bit signed)");
  }
  p.calibration = ina226::calibration(p.current_lsb, p.shunt_ohm);
  if (p.calibration == 0) {
    const auto where = root.find("current_lsb_a") ? root.at("current_lsb_a") : root.at("shunt_ohm");
    where.fail(
        "a current LSB and shunt for which CAL = 0.00512 / (current_lsb_a * shunt_ohm) is "
        "in 1..32767 (here " +
        std::to_string(0.00512 / (p.current_lsb * p.shunt_ohm)) + ")");
  }
  const auto avg = root.find("averaging");
  p.averaging = static_cast<int>(root.integer_or("averaging", p.averaging, 1, 1024));
  if (ina226::averaging_code(p.averaging) < 0)
    avg->fail("one of 1, 4, 16, 64, 128, 256, 512, 1024");
  const char* times = "one of 140, 204, 332, 588, 1100, 2116, 4156, 8244 (us)";
  p.bus_conversion_us =
      static_cast<int>(root.integer_or("bus_conversion_us", p.bus_conversion_us, 140, 8244));
  if (ina226::conversion_time_code(p.bus_conversion_us) < 0)
    root.at("bus_conversion_us").fail(times);
  p.shunt_conversion_us =
      static_cast<int>(root.integer_or("shunt_conversion_us", p.shunt_conversion_us, 140, 8244));
  if (ina226::conversion_time_code(p.shunt_conversion_us) < 0)
    root.at("shunt_conversion_us").fail(times);
  p.config = ina226::config_word(ina226::averaging_code(p.averaging),
                                 ina226::conversion_time_code(p.bus_conversion_us),
                                 ina226::conversion_time_code(p.shunt_conversion_us));
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {0.1, 1000});
  const auto conv_us =
      ina226::sample_period_us(p.averaging, p.bus_conversion_us, p.shunt_conversion_us);
  if (1e6 / p.rate_hz < static_cast<double>(conv_us)) {
    root.at("rate_hz").fail("at most " + std::to_string(1e6 / static_cast<double>(conv_us)) +
                            " Hz (one averaged conversion takes averaging x (bus + shunt "
                            "conversion) = " +
                            std::to_string(conv_us) + " us)");
  }
  p.invert_current = root.boolean_or("invert_current", p.invert_current);
  p.channel = root.string_or("channel", p.channel);
  p.max_gap = from_seconds(root.number_or("max_gap_s", 1.0, {0.001, 3600}));
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  p.fault_after = static_cast<int>(root.integer_or("fault_after", p.fault_after, 1, 1000));
  root.check_all_used();
  return p;
}

void fill_power_sample(power_t& msg, ina226::Integrator& integ, std::int64_t& gaps, TimeUs now,
                       double volts, double amps, double watts) {
  const auto gaps_before = integ.gaps();
  integ.add(now, amps, watts);
  gaps += integ.gaps() - gaps_before;
  msg.utime = now;
  msg.voltage = volts;
  msg.current = amps;
  msg.power = watts;
  msg.consumed_charge = integ.charge_ah();
  msg.consumed_energy = integ.energy_wh();
}

PowerParams load_power_file(const std::string& path) {
  return load_power_params(config::Value::load_file(path));
}

PowerNode::PowerNode(const PowerParams& p, i2c::Transport& bus)
    : Node("power", from_hz(p.rate_hz)),
      p_(p),
      bus_(bus),
      health_("ina226 on " + bus.name() + " at " + hex(p.address), p.retry_period, p.fault_after),
      degraded_(health_.where() + ": bus errors in the last second"),
      integ_(p.max_gap) {
  advertise<power_t>(p.channel);
  retries_ = &counter("bus.retries");
  bus_errors_ = &counter("bus.errors");
  init_failures_ = &counter("init.failures");
  resets_ = &counter("device.resets");
  gaps_ = &counter("charge.gaps");
  samples_ = &counter("samples");
  rejected_ = &counter("rejected.sample.range");
  msg_.monitor = "ina226@" + bus.name() + ":" + hex(p.address);
  set_health(heartbeat_t::STATE_FAULT, health_.where() + ": not set up yet");
}

int PowerNode::read16(std::uint8_t reg, std::uint16_t& v) {
  std::uint8_t b[2] = {0, 0};
  const int err = bus_.write_read(p_.address, &reg, 1, b, 2);
  v = static_cast<std::uint16_t>(b[0] << 8 | b[1]);
  return err;
}

int PowerNode::write16(std::uint8_t reg, std::uint16_t v) {
  const std::uint8_t b[3] = {reg, static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v)};
  return bus_.write(p_.address, b, 3);
}

int PowerNode::with_retry(auto&& op) {
  return retry_once(*retries_, op);
}

void PowerNode::lost(TimeUs now, int err, std::string_view why) {
  ready_ = false;
  set_health(heartbeat_t::STATE_FAULT, health_.down(now, err, why));
}

void PowerNode::set_up(TimeUs now) {
  std::uint16_t mfr = 0, die = 0, cfg = 0, cal = 0;
  int err = with_retry([&] { return read16(ina226::kRegManufacturerId, mfr); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegDieId, die); });
  if (err != 0) {
    ++*init_failures_;
    lost(now, err, "no answer (is it wired, powered, at that address?)");
    return;
  }
  if (mfr != ina226::kManufacturerId || die != ina226::kDieId) {
    ++*init_failures_;
    lost(now, 0,
         "MANUFACTURER_ID " + hex(mfr, 4) + " / DIE_ID " + hex(die, 4) +
             ", not 0x5449 / 0x2260: not an INA226 (an INA219 or INA260 at that address?)");
    return;
  }
  err = with_retry([&] { return write16(ina226::kRegConfig, ina226::kConfigReset); });
  if (err == 0) err = with_retry([&] { return write16(ina226::kRegConfig, p_.config); });
  if (err == 0) err = with_retry([&] { return write16(ina226::kRegCalibration, p_.calibration); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegConfig, cfg); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegCalibration, cal); });
  if (err != 0) {
    ++*init_failures_;
    lost(now, err, "set-up failed");
    return;
  }
  if (cfg != p_.config || cal != p_.calibration) {
    ++*init_failures_;
    lost(now, 0,
         "configuration / calibration read back " + hex(cfg, 4) + " / " + hex(cal, 4) +
             ", written " + hex(p_.config, 4) + " / " + hex(p_.calibration, 4));
    return;
  }
  ready_ = true;
  health_.succeeded();
  // The first averaged result is ready one conversion period after the configuration.
  next_step_ =
      now + ina226::sample_period_us(p_.averaging, p_.bus_conversion_us, p_.shunt_conversion_us);
  set_health(heartbeat_t::STATE_OK, health_.where());
}

void PowerNode::on_tick(TimeUs now) {
  bus_.set_time(now);
  if (!ready_) {
    if (health_.may_try(now)) set_up(now);
    return;
  }
  if (now < next_step_) return;
  sample(now);
}

void PowerNode::sample(TimeUs now) {
  std::uint16_t vbus = 0, cur = 0, pwr = 0, cal = 0;
  int err = with_retry([&] { return read16(ina226::kRegBus, vbus); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegCurrent, cur); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegPower, pwr); });
  if (err == 0) err = with_retry([&] { return read16(ina226::kRegCalibration, cal); });
  if (err != 0) {
    ++*bus_errors_;
    if (health_.failed(now)) {
      lost(now, err, std::to_string(health_.consecutive()) + " reads failed in a row");
    } else {
      set_health(heartbeat_t::STATE_DEGRADED, degraded_);
    }
    return;
  }
  health_.succeeded();
  if (cal != p_.calibration) {
    ++*resets_;
    health_.glitch(now);
    ready_ = false;  // set it up again at the next tick (may_try: no retry period after a reset)
    set_health(heartbeat_t::STATE_DEGRADED, health_.where() + ": calibration register reads " +
                                                hex(cal, 4) +
                                                " (the chip reset?); setting it up again");
    return;
  }
  const double sign = p_.invert_current ? -1.0 : 1.0;
  const double amps = sign * ina226::current(cur, p_.current_lsb);
  const double watts = std::copysign(ina226::power(pwr, p_.current_lsb), amps);
  fill_power_sample(msg_, integ_, *gaps_, now, ina226::bus_voltage(vbus), amps, watts);
  if (checks::check(msg_) != nullptr) {
    reject(*rejected_);
  } else {
    ++*samples_;
    publish(p_.channel, msg_);
  }
  if (health_.failed_recently(now)) {
    set_health(heartbeat_t::STATE_DEGRADED, degraded_);
  } else {
    set_health(heartbeat_t::STATE_OK, health_.where());
  }
}

}  // namespace tiller::sensors
