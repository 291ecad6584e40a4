#include "esc/esc_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <tiller/heartbeat_t.hpp>

#include "core/checks.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller {

namespace {
constexpr TimeUs k10Hz = 100'000;
constexpr double kRangeSlack = 1e-9;  // |u| up to 1 + this is clamped, beyond it rejected

std::string esc_where(const esc::EscBackend& b, std::size_t i) {
  char buf[64];
  if (b.unit() == esc_output_t::UNIT_PULSE_US && b.label() != "sim") {
    std::snprintf(buf, sizeof buf, "channel %d", b.channel(i).address);
  } else if (b.label() == "sim") {
    std::snprintf(buf, sizeof buf, "sim %d", b.channel(i).address);
  } else {
    std::snprintf(buf, sizeof buf, "0x%02x", b.channel(i).address);
  }
  return b.channel(i).name + " (" + buf + ")";
}
}  // namespace

// With write_on_command the node ticks every min_write_interval (so a command held back by
// the interval goes out at the next tick instead of the next cycle); the bus cycle itself stays
// on its own grid of 1 / rate_hz.
TimeUs EscNode::tick_period_for(const esc::EscNodeParams& p) {
  const TimeUs cycle = from_hz(p.rate_hz);
  const TimeUs w = p.min_write_interval_us;
  return p.write_on_command && w > 0 && w < cycle ? w : cycle;
}

EscNode::EscNode(esc::EscNodeParams p, std::unique_ptr<esc::EscBackend> backend)
    : Node("esc", tick_period_for(p)),
      p_(p),
      cycle_period_(from_hz(p.rate_hz)),
      backend_(std::move(backend)),
      n_(backend_->size()),
      command_(n_, 0.0),
      command_freshness_(p.command_timeout_us),
      motor_(n_, 0.0),
      hw_(n_, 0) {
  subscribe(channels::kThrusterCommand, &EscNode::on_command);
  subscribe(channels::kArmRequest, &EscNode::on_arm_request);
  // Thrust commands only from the mixer (config: command_senders): enforced by the transport
  // when signing is on (docs/safety.md, "Who may command").
  accept_only_from(channels::kThrusterCommand, p.command_senders);
  advertise<arm_state_t>(channels::kArmState);
  advertise<esc_output_t>(channels::kEscOutput);
  advertise<esc_bus_status_t>(channels::kEscStatus);
  advertise<esc_telemetry_t>(channels::kEscTelemetry);
  c_nan_ = &counter("rejected.command.nan");
  c_range_ = &counter("rejected.command.range");
  c_missing_ = &counter("rejected.command.missing_thruster");
  c_unknown_ = &counter("rejected.command.unknown_thruster");
  c_arm_refused_ = &counter("arm.refused_not_neutral");
  c_nonce_ = &counter("rejected.arm_request.boot_nonce");
  c_station_ = &counter("rejected.arm_request.station");
  c_takeovers_ = &counter("arm.takeovers");
  c_bus_errors_ = &counter("bus.errors");
  for (std::size_t i = 0; i < n_; ++i) hw_[i] = backend_->to_hardware(i, 0.0);
  init_messages();
  arm_.armed = false;
  arm_.session = 0;
  arm_.boot_nonce = 0;
  arm_.reason = "disarmed at start";
  set_health(heartbeat_t::STATE_OK, "starting: disarmed, neutral");
}

EscNode::EscNode(const std::string& config_path)
    : EscNode(esc::load_esc_config_file(config_path), nullptr) {}

EscNode::EscNode(const std::string& config_path, i2c::Transport& transport)
    : EscNode(esc::load_esc_config_file(config_path), &transport) {}

EscNode::EscNode(const esc::EscConfig& cfg, i2c::Transport* transport)
    : EscNode(cfg.node, esc::make_backend(cfg, transport)) {}

EscNode::~EscNode() = default;

void EscNode::init_messages() {
  const auto n = static_cast<std::int32_t>(n_);
  out_.backend = backend_->label();
  out_.unit = backend_->unit();
  out_.n_channels = n;
  out_.names.resize(n_);
  out_.channel.resize(n_);
  out_.value.resize(n_);
  out_.normalized.resize(n_);
  status_.backend = backend_->label();
  status_.bus = backend_->bus();
  status_.n_escs = n;
  status_.names.resize(n_);
  status_.present.resize(n_);
  status_.write_errors.resize(n_);
  status_.read_errors.resize(n_);
  status_.last_errno.resize(n_);
  telem_.n_escs = n;
  telem_.names.resize(n_);
  telem_.address.resize(n_);
  telem_.sample_utime.resize(n_);
  telem_.rpm.resize(n_);
  telem_.voltage.resize(n_);
  telem_.current.resize(n_);
  telem_.temperature.resize(n_);
  telem_.alive.resize(n_);
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& c = backend_->channel(i);
    out_.names[i] = c.name;
    out_.channel[i] = c.address;
    out_.value[i] = hw_[i];
    out_.normalized[i] = 0.0;
    status_.names[i] = c.name;
    telem_.names[i] = c.name;
    telem_.address[i] = c.address;
  }
}

esc::StartReport EscNode::start(TimeUs now) {
  if (started_) return start_report_;
  started_ = true;
  start_report_ = backend_->start(now);
  update_health();
  return start_report_;
}

void EscNode::on_command(const thruster_command_t& m, TimeUs now) {
  if (!on_time(command_freshness_, m.utime, now, "command")) return;
  if (m.n_thrusters < 0 || m.n_thrusters > 16) {
    reject(*c_missing_);
    return;
  }
  if (!checks::detail::source(m.source)) {  // its contract: a wrench_t SOURCE_* constant
    if (c_source_ == nullptr) c_source_ = &counter("rejected.command.source");  // on first use
    reject(*c_source_);
    return;
  }
  const auto n = static_cast<std::size_t>(m.n_thrusters);
  // Map message positions to ESCs; rebuilt only when the names change.
  if (m.names != cached_names_) {
    cached_names_ = m.names;
    cached_map_.assign(n, -1);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t i = 0; i < n_; ++i) {
        if (backend_->channel(i).name == m.names[k]) cached_map_[k] = static_cast<int>(i);
      }
    }
  }
  std::size_t covered = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (cached_map_[k] < 0) {
      reject(*c_unknown_);
      return;
    }
    bool dup = false;
    for (std::size_t j = 0; j < k; ++j) dup = dup || cached_map_[j] == cached_map_[k];
    if (!dup) ++covered;
  }
  if (covered != n_ || n != n_) {
    reject(*c_missing_);
    return;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const double v = m.command[k];
    if (!std::isfinite(v)) {
      reject(*c_nan_);
      return;
    }
    if (std::abs(v) > 1.0 + kRangeSlack) {
      reject(*c_range_);
      return;
    }
  }
  bool changed = false;
  for (std::size_t k = 0; k < n; ++k) {
    double& c = command_[static_cast<std::size_t>(cached_map_[k])];
    const double v = std::clamp(m.command[k], -1.0, 1.0);
    changed = changed || v != c;
    c = v;
  }
  arm_allowed_ = m.arm_allowed;
  if (!m.arm_allowed && hold_ != m.hold) hold_ = m.hold;
  command_freshness_.mark(now, m.utime, clock_offset());
  command_fresh_ = true;
  // A changed command goes out at once (armed only: disarmed, the cycle's neutral is all there
  // is to send). An unchanged one (the mixer's fixed-rate repeats) waits for the cycle, so it
  // does not use up the interval. The cycle's own writes do not count against the interval
  // either: a command that arrives just after a cycle still goes out at once.
  // One held back by the interval is written at the first tick the interval allows.
  if (p_.write_on_command && changed && armed_ && started_) {
    if (!have_extra_write_ || now - last_extra_write_ >= p_.min_write_interval_us) {
      write_extra(now);
    } else {
      pending_ = true;
    }
  }
}

bool EscNode::commands_neutral(TimeUs now, std::size_t* worst) {
  if (!command_freshness_.fresh(now)) return true;  // no command: the output is neutral
  double w = 0;
  for (std::size_t i = 0; i < n_; ++i) {
    if (std::abs(command_[i]) > w) {
      w = std::abs(command_[i]);
      *worst = i;
    }
  }
  return w <= p_.arm_neutral_tolerance;
}

void EscNode::on_arm_request(const arm_request_t& m, TimeUs now) {
  const std::string who = (m.source.empty() ? std::string("unknown") : m.source) +
                          (m.station.empty() ? std::string() : " at station " + m.station);
  if (!m.arm) {  // any station may stop the vehicle
    set_armed(false, "disarmed by " + who, now);
    return;
  }
  if (m.boot_nonce != arm_.boot_nonce) {
    reject(*c_nonce_);
    arm_.reason = "arm refused (asked by " + who +
                  "): the request is for another start of tiller-esc (boot nonce differs: "
                  "replayed, or sent before a restart)";
    publish_arm_state(now);
    return;
  }
  if (armed_ && m.station == arm_.controller) {
    publish_arm_state(now);  // already armed for this station
    return;
  }
  // An arm request is an event: one that waited (in the queue of a stopped process, say) is
  // refused, counted in rejected.arm_request.stale / .future. A disarm is always taken.
  if (!on_time(m.utime, now, kEventMaxAgeUs, "arm_request")) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%+.3f s", to_seconds(m.utime - now));
    arm_.reason = "arm refused (asked by " + who + "): the request is stamped " + buf +
                  " from this clock (stale or a clock out of step)";
    publish_arm_state(now);
    return;
  }
  if (armed_ && !m.takeover) {
    reject(*c_station_);
    arm_.reason = "arm refused (asked by " + who + "): another station in control: " +
                  (arm_.controller.empty() ? std::string("(none named)") : arm_.controller);
    publish_arm_state(now);
    return;
  }
  if (armed_) {  // a takeover: a new session, so the mixer waits for the new station's stick
    ++*c_takeovers_;
    const std::string from = arm_.controller.empty() ? "(none named)" : arm_.controller;
    ++session_;
    arm_.controller = m.station;
    set_armed(true, "control taken by " + (m.station.empty() ? who : m.station) + " from " + from,
              now);
    return;
  }
  std::size_t worst = 0;
  if (!commands_neutral(now, &worst)) {
    ++*c_arm_refused_;
    char buf[96];
    std::snprintf(buf, sizeof buf, " = %.3f", command_[worst]);
    arm_.reason = "arm refused (asked by " + who + "): thruster command not neutral, " +
                  backend_->channel(worst).name + buf;
    publish_arm_state(now);
    return;
  }
  if (command_freshness_.fresh(now) && !arm_allowed_) {
    ++*c_arm_refused_;
    arm_.reason =
        "arm refused (asked by " + who + "): " + (hold_.empty() ? "mixer says no" : hold_);
    publish_arm_state(now);
    return;
  }
  ++session_;
  arm_.controller = m.station;
  set_armed(true, "armed by " + who, now);
}

void EscNode::set_armed(bool armed, const std::string& reason, TimeUs now) {
  armed_ = armed;
  if (!armed) std::fill(motor_.begin(), motor_.end(), 0.0);
  if (!armed && !arm_.controller.empty()) arm_.controller.clear();
  if (arm_.reason != reason) arm_.reason = reason;
  publish_arm_state(now);
}

void EscNode::publish_arm_state(TimeUs now) {
  arm_.utime = now;
  arm_.armed = armed_;
  arm_.session = session_;
  publish(channels::kArmState, arm_);
}

void EscNode::on_tick(TimeUs now) {
  if (!started_) start(now);
  command_fresh_ = command_freshness_.fresh(now);
  const std::int64_t se = command_freshness_.stale_events();
  if (se != last_stale_events_) {
    timeouts_ += se - last_stale_events_;
    count_stale(se - last_stale_events_);
    last_stale_events_ = se;
    if (armed_ && p_.disarm_on_timeout) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "disarmed: command timeout (no thruster command for %lld ms)",
                    static_cast<long long>(p_.command_timeout_us / 1000));
      set_armed(false, buf, now);
    }
  }
  if (now >= next_cycle_) {
    write_cycle(now, false, /*poll_telemetry=*/true);
    pending_ = false;  // the cycle carried the latest command
    next_cycle_ = (now / cycle_period_ + 1) * cycle_period_;
  } else if (pending_ && armed_ && now - last_extra_write_ >= p_.min_write_interval_us) {
    write_extra(now);
  }
  if (now >= next_10hz_) {
    publish_arm_state(now);
    publish_status(now);
    publish_telemetry(now);
    update_health();
    next_10hz_ = (now / k10Hz + 1) * k10Hz;
  }
}

void EscNode::write_extra(TimeUs now) {
  last_extra_write_ = now;
  have_extra_write_ = true;
  pending_ = false;
  write_cycle(now, false, /*poll_telemetry=*/false);
}

void EscNode::write_cycle(TimeUs now, bool force_neutral, bool poll_telemetry) {
  double dt = have_cycle_ ? to_seconds(now - last_cycle_) : to_seconds(cycle_period_);
  dt = std::clamp(dt, 0.0, 1.0);
  last_cycle_ = now;
  have_cycle_ = true;
  const bool active = !force_neutral && armed_ && command_fresh_;
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& c = backend_->channel(i);
    double m = 0.0;
    if (active) {
      const double target = (c.reversed ? -1.0 : 1.0) * c.trim * command_[i];
      m = motor_[i];
      if (c.slew_per_s > 0) {
        const double step = c.slew_per_s * dt;
        if (m * target < 0) {
          // Reversal: ramp down to exactly zero first; the next cycle starts the other way.
          m = std::abs(m) <= step ? 0.0 : m - std::copysign(step, m);
        } else {
          m += std::clamp(target - m, -step, step);
        }
      } else {
        m = target;
      }
    }
    motor_[i] = m;
    hw_[i] = backend_->to_hardware(i, m);
  }
  backend_->write(hw_.data(), now);
  // Telemetry is read on the cycle only (round robin, one ESC per cycle), never on a
  // command-triggered write, so the reads keep their steady share of the bus.
  if (poll_telemetry) backend_->poll_telemetry(now);
  ++cycles_;
  out_.utime = now;
  out_.armed = active;
  for (std::size_t i = 0; i < n_; ++i) {
    out_.value[i] = hw_[i];
    out_.normalized[i] = backend_->to_normalized(i, hw_[i]);
  }
  publish(channels::kEscOutput, out_);
}

void EscNode::publish_status(TimeUs now) {
  status_.utime = now;
  status_.armed = armed_;
  status_.command_timeout = !command_fresh_;
  status_.cycles = cycles_;
  status_.timeouts = timeouts_;
  std::int64_t errors = 0;
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& s = backend_->stats(i);
    status_.present[i] = s.present;
    status_.write_errors[i] = s.write_errors;
    status_.read_errors[i] = s.read_errors;
    status_.last_errno[i] = s.last_errno;
    errors += s.write_errors + s.read_errors;
  }
  *c_bus_errors_ = errors;
  publish(channels::kEscStatus, status_);
}

void EscNode::publish_telemetry(TimeUs now) {
  telem_.utime = now;
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& t = backend_->telemetry(i);
    telem_.sample_utime[i] = t.sample_utime;
    telem_.rpm[i] = t.rpm;
    telem_.voltage[i] = t.voltage;
    telem_.current[i] = t.current;
    telem_.temperature[i] = t.temperature;
    telem_.alive[i] = t.alive;
  }
  publish(channels::kEscTelemetry, telem_);
}

void EscNode::update_health() {
  // A small code for the situation; the status text is built only when it changes.
  int code = armed_ ? 1 : 0;
  std::size_t who = 0;
  std::size_t missing = 0, failing = 0;
  for (std::size_t i = 0; i < n_; ++i) {
    const auto& s = backend_->stats(i);
    if (!s.present) {
      if (missing++ == 0) who = i;
    } else if (s.consecutive_errors > 0) {
      if (failing++ == 0 && missing == 0) who = i;
    }
  }
  if (n_ > 0 && missing == n_) {
    code = 100;
  } else if (missing > 0) {
    code = 200 + static_cast<int>(who);
  } else if (failing > 0) {
    code = 300 + static_cast<int>(who) + 20 * backend_->stats(who).last_errno;
  } else if (armed_ && !command_fresh_) {
    code = 2;
  }
  if (code == health_code_) return;
  health_code_ = code;
  const std::string state = armed_ ? "armed" : "disarmed";
  if (code == 100) {
    set_health(heartbeat_t::STATE_FAULT, "no ESC answers on " + backend_->bus() + "; " + state);
  } else if (code >= 200 && code < 300) {
    set_health(heartbeat_t::STATE_DEGRADED,
               "ESC missing: " + esc_where(*backend_, who) + " (" +
                   i2c::describe_errno(backend_->stats(who).last_errno) + ")" +
                   (missing > 1 ? " and " + std::to_string(missing - 1) + " more" : "") + "; " +
                   state);
  } else if (code >= 300) {
    set_health(heartbeat_t::STATE_DEGRADED,
               "bus errors on " + esc_where(*backend_, who) + ": " +
                   i2c::describe_errno(backend_->stats(who).last_errno) + "; " + state);
  } else if (code == 2) {
    set_health(heartbeat_t::STATE_DEGRADED, "armed, no thruster command: neutral");
  } else if (code == 1) {
    set_health(heartbeat_t::STATE_OK, "armed");
  } else {
    set_health(heartbeat_t::STATE_OK, "disarmed: neutral");
  }
}

void EscNode::shutdown(TimeUs now) {
  if (!started_) start(now);
  set_armed(false, "shutdown: neutral written to every ESC", now);
  write_cycle(now, true, /*poll_telemetry=*/false);
  publish_status(now);
}

}  // namespace tiller
