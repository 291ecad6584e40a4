#include "sensors/ads1115_power_node.hpp"

#include <cerrno>
#include <cmath>

#include "core/config.hpp"
#include "core/message_checks.hpp"
#include "sensors/power_node.hpp"

namespace tiller::sensors {

Ads1115PowerParams load_ads1115_power_params(const config::Value& root) {
  Ads1115PowerParams p;
  if (root.string_or("device", "ads1115") != "ads1115") root.at("device").fail("ads1115");
  p.bus = root.string_or("bus", p.bus);
  p.address = static_cast<std::uint8_t>(root.integer_or("address", p.address, 0x48, 0x4B));
  auto& m = p.module;
  m.voltage_channel = static_cast<int>(root.integer_or("voltage_channel", m.voltage_channel, 0, 3));
  m.current_channel = static_cast<int>(root.integer_or("current_channel", m.current_channel, 0, 3));
  if (m.voltage_channel == m.current_channel)
    root.at("current_channel").fail("an input other than voltage_channel");
  m.voltage_divider = root.number_or("voltage_divider", m.voltage_divider, {0.01, 1000});
  m.amps_per_volt = root.number_or("amps_per_volt", m.amps_per_volt, {1e-3, 1e4});
  m.current_offset_v = root.number_or("current_offset_v", m.current_offset_v, {-6.144, 6.144});
  p.full_scale_v = root.number_or("full_scale_v", p.full_scale_v, {0.256, 6.144});
  if (ads1115::pga_code(p.full_scale_v) < 0)
    root.at("full_scale_v").fail("one of 6.144, 4.096, 2.048, 1.024, 0.512, 0.256 (V)");
  p.data_rate_sps = static_cast<int>(root.integer_or("data_rate_sps", p.data_rate_sps, 8, 860));
  if (ads1115::data_rate_code(p.data_rate_sps) < 0)
    root.at("data_rate_sps").fail("one of 8, 16, 32, 64, 128, 250, 475, 860");
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, {0.2, 1000});
  const auto conv = ads1115::conversion_us(ads1115::data_rate_code(p.data_rate_sps));
  if (1e6 / p.rate_hz < static_cast<double>(conv))
    root.at("rate_hz").fail("at most " + std::to_string(1e6 / static_cast<double>(conv)) +
                            " Hz (one conversion at data_rate_sps takes " + std::to_string(conv) +
                            " us)");
  p.invert_current = root.boolean_or("invert_current", p.invert_current);
  p.channel = root.string_or("channel", p.channel);
  p.max_gap = from_seconds(root.number_or("max_gap_s", 1.0, {0.001, 3600}));
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  p.fault_after = static_cast<int>(root.integer_or("fault_after", p.fault_after, 1, 1000));
  root.check_all_used();
  return p;
}

Ads1115PowerNode::Ads1115PowerNode(const Ads1115PowerParams& p, i2c::Transport& bus)
    : Node("power", from_hz(p.rate_hz)),
      p_(p),
      bus_(bus),
      dev_(bus, p.address, ads1115::pga_code(p.full_scale_v),
           ads1115::data_rate_code(p.data_rate_sps)),
      health_("ads1115 on " + bus.name() + " at " + hex(p.address), p.retry_period, p.fault_after),
      degraded_(health_.where() + ": bus errors in the last second"),
      integ_(p.max_gap) {
  advertise<power_t>(p.channel);
  retries_ = &counter("bus.retries");
  bus_errors_ = &counter("bus.errors");
  init_failures_ = &counter("init.failures");
  not_ready_ = &counter("conversion.not_ready");
  gaps_ = &counter("charge.gaps");
  samples_ = &counter("samples");
  rejected_ = &counter("rejected.sample.range");
  msg_.monitor = "ads1115@" + bus.name() + ":" + hex(p.address);
  set_health(heartbeat_t::STATE_FAULT, health_.where() + ": not set up yet");
}

int Ads1115PowerNode::with_retry(auto&& op) {
  return retry_once(*retries_, op);
}

void Ads1115PowerNode::failed(TimeUs now, int err) {
  ++*bus_errors_;
  if (health_.failed(now)) {
    ready_ = false;
    set_health(heartbeat_t::STATE_FAULT,
               health_.down(now, err,
                            std::to_string(health_.consecutive()) + " transfers failed in a row"));
  } else {
    set_health(heartbeat_t::STATE_DEGRADED, degraded_);
  }
}

void Ads1115PowerNode::on_tick(TimeUs now) {
  bus_.set_time(now);
  if (!ready_) {
    if (!health_.may_try(now)) return;
    int err = with_retry([&] { return dev_.probe(); });
    if (err == 0) err = with_retry([&] { return dev_.start(p_.module.voltage_channel); });
    if (err != 0) {
      ++*init_failures_;
      set_health(
          heartbeat_t::STATE_FAULT,
          health_.down(now, err,
                       err == EPROTO ? "its config register does not read like an ADS1115"
                                     : "no answer (is it wired, powered, at that address?)"));
      return;
    }
    ready_ = true;
    reading_current_ = false;
    have_voltage_ = false;
    read_at_ = now + ads1115::conversion_us(dev_.dr());
    health_.succeeded();
    set_health(heartbeat_t::STATE_OK, health_.where());
    return;
  }
  if (now < read_at_) return;
  sample(now);
}

void Ads1115PowerNode::sample(TimeUs now) {
  // Done? The config register's OS bit reads 1 once the single conversion has finished.
  std::uint8_t reg = ads1115::kRegConfig, b[2] = {0, 0};
  int err = with_retry([&] { return bus_.write_read(p_.address, &reg, 1, b, 2); });
  if (err != 0) return failed(now, err);
  if (!(b[0] & 0x80)) {
    ++*not_ready_;
    return;  // read at the next tick
  }
  std::uint16_t raw = 0;
  err = with_retry([&] { return dev_.read(raw); });
  if (err == 0) {
    err = with_retry([&] {
      return dev_.start(reading_current_ ? p_.module.voltage_channel : p_.module.current_channel);
    });
  }
  if (err != 0) return failed(now, err);
  health_.succeeded();
  read_at_ = now + ads1115::conversion_us(dev_.dr());
  const double v_in = ads1115::volts(raw, dev_.pga());
  const bool was_current = reading_current_;
  reading_current_ = !reading_current_;
  if (!was_current) {
    bus_v_ = p_.module.voltage_divider * v_in;
    have_voltage_ = true;
  } else if (have_voltage_) {
    const double amps = (p_.invert_current ? -1.0 : 1.0) * (v_in - p_.module.current_offset_v) *
                        p_.module.amps_per_volt;
    fill_power_sample(msg_, integ_, *gaps_, now, bus_v_, amps, bus_v_ * amps);
    if (checks::check(msg_) != nullptr) {
      reject(*rejected_);
    } else {
      ++*samples_;
      publish(p_.channel, msg_);
    }
  }
  if (health_.failed_recently(now)) {
    set_health(heartbeat_t::STATE_DEGRADED, degraded_);
  } else {
    set_health(heartbeat_t::STATE_OK, health_.where());
  }
}

}  // namespace tiller::sensors
