#include "sensors/pressure_node.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>

#include "core/config.hpp"
#include "core/message_checks.hpp"

namespace tiller::sensors {

namespace {
constexpr double kG = 9.80665;  // m/s^2, standard gravity (the contract's depth formula)

const char* model_name(ms5837::Model m) {
  return m == ms5837::Model::ba30 ? "ms5837-30ba" : "ms5837-02ba";
}
}  // namespace

PressureParams load_pressure_params(const config::Value& root) {
  PressureParams p;
  p.bus = root.string_or("bus", p.bus);
  p.address = static_cast<std::uint8_t>(root.integer_or("address", p.address, 0x76, 0x77));
  p.model = root.choice_or("model", "ms5837-30ba", {"ms5837-30ba", "ms5837-02ba"}) == "ms5837-30ba"
                ? ms5837::Model::ba30
                : ms5837::Model::ba02;
  const auto osr = root.find("osr");
  const int ratio = static_cast<int>(root.integer_or("osr", 4096, 256, 8192));
  p.osr = ms5837::osr_for(ratio);
  if (p.osr.ratio == 0) osr->fail("one of 256, 512, 1024, 2048, 4096, 8192");
  p.rate_hz = root.number_or("rate_hz", p.rate_hz, config::Range::positive());
  const double tick_us = 1e6 / (2 * p.rate_hz);
  if (tick_us <= static_cast<double>(p.osr.max_conversion_us)) {
    root.at("rate_hz").fail(
        "a rate whose half period exceeds the OSR " + std::to_string(ratio) +
        " conversion time of " + std::to_string(p.osr.max_conversion_us) + " us (at most " +
        std::to_string(static_cast<int>(5e5 / p.osr.max_conversion_us)) + " Hz)");
  }
  const std::string water = root.choice_or("water", "fresh", {"fresh", "salt", "custom"});
  p.water_density = water == "fresh" ? 997.0 : 1025.0;
  if (water == "custom") p.water_density = root.number("water_density", {900, 1100});
  p.surface_pressure = root.number_or("surface_pressure_pa", p.surface_pressure, {5e4, 1.2e5});
  p.channel = root.string_or("channel", p.channel);
  p.retry_period = from_seconds(root.number_or("retry_period_s", 1.0, {0.01, 3600}));
  p.fault_after = static_cast<int>(root.integer_or("fault_after", p.fault_after, 1, 1000));
  root.check_all_used();
  return p;
}

PressureParams load_pressure_file(const std::string& path) {
  return load_pressure_params(config::Value::load_file(path));
}

PressureNode::PressureNode(const PressureParams& p, i2c::Transport& bus)
    : Node("pressure", from_hz(2 * p.rate_hz)),
      p_(p),
      bus_(bus),
      dev_(bus, p.address, p.model, p.osr),
      health_(std::string(model_name(p.model)) + " on " + bus.name() + " at " + hex(p.address),
              p.retry_period, p.fault_after) {
  advertise<pressure_t>(p.channel);
  retries_ = &counter("bus.retries");
  bus_errors_ = &counter("bus.errors");
  crc_errors_ = &counter("prom.crc_errors");
  not_ready_ = &counter("adc.not_ready");
  samples_ = &counter("samples");
  init_failures_ = &counter("init.failures");
  rejected_sample_ = &counter("rejected.sample.range");
  msg_.water_density = p.water_density;
  msg_.surface_pressure = p.surface_pressure;
  msg_.sensor = std::string(model_name(p.model)) + "@" + bus.name() + ":" + hex(p.address);
  set_health(heartbeat_t::STATE_FAULT, health_.where() + ": not set up yet");
}

// Not worth a second try: the conversion is not finished yet, or the PROM's CRC is wrong.
int PressureNode::with_retry(auto&& op) {
  return retry_once(*retries_, op, [](int err) { return err == EAGAIN || err == EBADMSG; });
}

void PressureNode::lost(TimeUs now, int err, const char* step) {
  ready_ = false;
  have_d2_ = false;
  set_health(heartbeat_t::STATE_FAULT, health_.down(now, err, step));
}

void PressureNode::sample_failed(TimeUs now, int err, const char* step) {
  if (err == EAGAIN) {
    ++*not_ready_;
  } else {
    ++*bus_errors_;
  }
  if (health_.failed(now)) {
    lost(now, err, step);
    return;
  }
  // Start the same conversion again next tick.
  const bool pressure = converting_pressure_;
  with_retry([&] { return dev_.start_conversion(pressure); });
}

void PressureNode::update_health(TimeUs now) {
  if (!ready_) return;
  if (health_.failed_recently(now)) {
    set_health(heartbeat_t::STATE_DEGRADED, health_.where() + ": bus errors in the last second");
  } else {
    set_health(heartbeat_t::STATE_OK, health_.where());
  }
}

void PressureNode::on_tick(TimeUs now) {
  bus_.set_time(now);
  if (!ready_) {
    if (!health_.may_try(now)) return;
    int err = with_retry([&] { return dev_.start(); });
    if (err == 0) {
      converting_pressure_ = false;
      err = with_retry([&] { return dev_.start_conversion(false); });
    }
    if (err != 0) {
      ++*init_failures_;
      if (err == EBADMSG) {
        ++*crc_errors_;
        lost(now, err, "PROM CRC-4 mismatch (a damaged or different sensor)");
      } else {
        lost(now, err, "no answer (is it wired, powered, at that address?)");
      }
      return;
    }
    ready_ = true;
    health_.succeeded();
    update_health(now);
    return;
  }
  std::uint32_t v = 0;
  const int err = with_retry([&] { return dev_.read_adc(v); });
  if (err != 0) {
    sample_failed(now, err, converting_pressure_ ? "D1 read" : "D2 read");
    update_health(now);
    return;
  }
  health_.succeeded();
  const bool was_pressure = converting_pressure_;
  converting_pressure_ = !converting_pressure_;
  const int e2 = with_retry([&] { return dev_.start_conversion(converting_pressure_); });
  if (e2 != 0) {
    converting_pressure_ = was_pressure;  // read again after a fresh start of the same one
    sample_failed(now, e2, "conversion start");
  }
  if (!was_pressure) {
    d2_ = v;
    have_d2_ = true;
  } else if (have_d2_) {
    const ms5837::Result r = ms5837::compensate(p_.model, dev_.prom(), v, d2_);
    msg_.utime = now;
    msg_.pressure = r.pressure_pa;
    msg_.temperature = r.temperature_c;
    msg_.depth = (r.pressure_pa - p_.surface_pressure) / (p_.water_density * kG);
    if (checks::check(msg_) != nullptr) {
      reject(*rejected_sample_);
    } else {
      ++*samples_;
      publish(p_.channel, msg_);
    }
  }
  update_health(now);
}

}  // namespace tiller::sensors
