#include "esc/esc_config.hpp"

#include <algorithm>
#include <filesystem>
#include <set>

#include "esc/dry_run.hpp"
#include "esc/sim_backend.hpp"
#include "i2c/linux_i2c.hpp"

namespace tiller::esc {

namespace {

PulseRange load_pulse(const config::Value& v, const PulseRange& def) {
  PulseRange r;
  const config::Range us{500, 2500};
  r.min_us = v.number_or("min_us", def.min_us, us);
  r.neutral_us = v.number_or("neutral_us", def.neutral_us, us);
  r.max_us = v.number_or("max_us", def.max_us, us);
  if (!(r.min_us < r.neutral_us && r.neutral_us < r.max_us)) {
    v.fail("min_us < neutral_us < max_us (got " + std::to_string(r.min_us) + ", " +
           std::to_string(r.neutral_us) + ", " + std::to_string(r.max_us) + ")");
  }
  return r;
}

TgyParams load_tgy(const config::Value& v) {
  TgyParams p;
  p.bus = v.string_or("bus", p.bus);
  p.telemetry = v.boolean_or("telemetry", p.telemetry);
  p.motor_poles = static_cast<int>(v.integer_or("motor_poles", p.motor_poles, 2, 64));
  return p;
}

Pca9685Params load_pca(const config::Value& v) {
  Pca9685Params p;
  p.bus = v.string_or("bus", p.bus);
  p.address = static_cast<int>(v.integer_or("address", p.address, 0x03, 0x77));
  p.pwm_hz = v.number_or("pwm_hz", p.pwm_hz, {24, 1526});
  p.oscillator_hz = v.number_or("oscillator_hz", p.oscillator_hz, {1e6, 50e6});
  p.oscillator_calibration = v.number_or("oscillator_calibration", 1.0, {0.8, 1.2});
  p.external_clock_hz = v.number_or("external_clock_hz", 0.0, {0, 50e6});
  p.totem_pole = v.choice_or("output", "totem_pole", {"totem_pole", "open_drain"}) == "totem_pole";
  p.pulse = load_pulse(v, p.pulse);
  if (const auto oe = v.find("output_enable")) {
    p.oe_chip = oe->string_or("chip", p.oe_chip);
    p.oe_line = static_cast<int>(oe->integer("line", 0, 511));
  }
  const int pre = pca9685::prescale(p);
  if (pre < 3 || pre > 255) {
    v.at("pwm_hz").fail("a PWM frequency giving a prescale in 3..255 with this clock (got " +
                        std::to_string(pre) + ")");
  }
  return p;
}

// Thruster names and `reversed` flags from the vehicle file (the vehicle loader owns the rest).
std::vector<std::pair<std::string, bool>> load_vehicle_thrusters(const std::string& path) {
  const config::Value root = config::Value::load_file(path);
  std::vector<std::pair<std::string, bool>> out;
  for (const auto& t : root.at("thrusters").items()) {
    out.emplace_back(t.string("name"), t.boolean_or("reversed", false));
  }
  root.mark_used();
  return out;
}

}  // namespace

EscConfig load_esc_config(const config::Value& root) {
  EscConfig c;
  c.file = root.file();
  const std::string veh = root.string("vehicle");
  std::filesystem::path vp(veh);
  if (vp.is_relative()) vp = std::filesystem::path(c.file).parent_path() / vp;
  c.vehicle_file = vp.lexically_normal().string();
  if (!std::filesystem::exists(vp))
    root.at("vehicle").fail("an existing vehicle file (" + c.vehicle_file + " not found)");

  c.backend = root.choice("backend", {"i2c_tgy", "pca9685", "sim", "dry_run"});
  c.node.rate_hz = root.number_or("rate_hz", 100, {1, 2000});
  c.node.command_timeout_us =
      from_seconds(root.number_or("command_timeout_ms", 250, {10, 10000}) / 1000.0);
  c.node.disarm_on_timeout = root.boolean_or("disarm_on_timeout", true);
  c.node.arm_neutral_tolerance = root.number_or("arm_neutral_tolerance", 0.02, {0, 0.2});
  c.node.write_on_command = root.boolean_or("write_on_command", true);
  c.node.min_write_interval_us =
      from_seconds(root.number_or("min_write_interval_ms", 2, {0, 1000}) / 1000.0);
  if (auto v = root.find("command_senders")) {
    c.node.command_senders.clear();
    for (const auto& item : v->items()) {
      const std::string name = item.as_string();
      if (name.empty() || name.size() > 16)
        item.fail("a node name of 1 to 16 characters (the sender in a signed message)");
      c.node.command_senders.push_back(name);
    }
    if (c.node.command_senders.empty()) v->fail("a list of at least one sender, e.g. [mixer]");
  }
  c.node.missing_esc = root.choice_or("missing_esc", "refuse", {"refuse", "degraded"}) == "refuse"
                           ? MissingEscPolicy::kRefuse
                           : MissingEscPolicy::kDegraded;

  // Every backend section present is checked; the chosen one is used.
  if (auto v = root.find("i2c_tgy")) c.tgy = load_tgy(*v);
  if (auto v = root.find("pca9685")) c.pca9685 = load_pca(*v);
  PulseRange sim_pulse;
  if (auto v = root.find("sim")) {
    c.sim_pulse_us =
        v->choice_or("unit", "throttle_int16", {"throttle_int16", "pulse_us"}) == "pulse_us";
    sim_pulse = load_pulse(*v, sim_pulse);
  }
  if (auto v = root.find("dry_run")) {
    c.dry_run.protocol = v->choice_or("protocol", "i2c_tgy", {"i2c_tgy", "pca9685"});
    c.dry_run.every_cycle =
        v->choice_or("print", "changes", {"changes", "every_cycle"}) == "every_cycle";
    if (auto u = v->find("unplugged")) {
      if (!u->is_sequence()) u->fail("a list of I2C addresses");
      u->mark_used();  // an empty list has no items to read
      for (const auto& a : u->items()) {
        c.dry_run.unplugged.push_back(static_cast<int>(a.as_integer(0x03, 0x77)));
      }
    }
  }
  const std::string proto = c.backend == "dry_run" ? c.dry_run.protocol : c.backend;
  // The hardware backends need their section (the bus, the board); at() throws naming it.
  if (c.backend == "i2c_tgy" && !root.has("i2c_tgy")) root.at("i2c_tgy");
  if (proto == "pca9685" && !root.has("pca9685")) root.at("pca9685");

  const auto thrusters = load_vehicle_thrusters(c.vehicle_file);
  const config::Value escs = root.at("escs");
  if (!escs.is_sequence() || escs.size() == 0) escs.fail("a list of ESCs, one per thruster");
  if (escs.size() > 16) escs.fail("at most 16 ESCs");
  std::set<std::string> names;
  std::set<int> addrs;
  std::size_t idx = 0;
  for (const auto& e : escs.items()) {
    EscChannelParams ch;
    ch.name = e.string("name");
    if (!names.insert(ch.name).second)
      e.at("name").fail("a thruster name used once (" + ch.name + " repeats)");
    bool found = false;
    for (const auto& [n, rev] : thrusters) {
      if (n == ch.name) {
        found = true;
        ch.reversed = rev;
      }
    }
    if (!found) {
      std::string list;
      for (const auto& t : thrusters) list += (list.empty() ? "" : ", ") + t.first;
      e.at("name").fail("a thruster of " + c.vehicle_file + " (" + list + "), got " + ch.name);
    }
    if (proto == "i2c_tgy") {
      ch.address = static_cast<int>(e.integer("address", 0x03, 0x77));
      if (!addrs.insert(ch.address).second) e.at("address").fail("an I2C address used once");
    } else if (proto == "pca9685") {
      ch.address = static_cast<int>(e.integer("channel", 0, 15));
      if (!addrs.insert(ch.address).second) e.at("channel").fail("a board channel used once");
    } else {
      ch.address = static_cast<int>(
          e.has("address") ? e.integer("address", 0, 0x77)
                           : e.integer_or("channel", static_cast<std::int64_t>(idx), 0, 15));
    }
    ch.trim = e.number_or("trim", 1.0, {0.05, 1.0});
    ch.slew_per_s = e.number_or("slew_per_s", 0.0, {0, 1000});
    // Pulse widths mean something only for PWM (and the sim in pulse units): elsewhere they
    // are unknown keys.
    if (proto == "pca9685") {
      ch.pulse = load_pulse(e, c.pca9685.pulse);
    } else if (proto == "sim") {
      ch.pulse = load_pulse(e, sim_pulse);
    }
    if (e.has("reversed")) {
      e.at("reversed")
          .fail("no `reversed` here: a thruster is reversed in the vehicle file (" +
                c.vehicle_file + "), the one place for it");
    }
    c.escs.push_back(ch);
    ++idx;
  }
  for (const auto& t : thrusters) {
    if (!names.count(t.first)) {
      escs.fail("an ESC for every thruster of " + c.vehicle_file + "; thruster " + t.first +
                " has none");
    }
  }
  root.check_all_used();
  return c;
}

EscConfig load_esc_config_file(const std::string& path) {
  return load_esc_config(config::Value::load_file(path));
}

std::unique_ptr<EscBackend> make_backend(const EscConfig& cfg, i2c::Transport* transport,
                                         std::FILE* dry_run_out) {
  if (cfg.backend == "sim") return std::make_unique<SimBackend>(cfg.escs, cfg.sim_pulse_us);
  std::shared_ptr<i2c::Transport> owned;
  const std::string proto = cfg.backend == "dry_run" ? cfg.dry_run.protocol : cfg.backend;
  if (cfg.backend == "dry_run") {
    auto dry = std::make_shared<DryRunTransport>(dry_run_out, cfg.dry_run.every_cycle);
    auto plugged = [&](int a) {
      return std::find(cfg.dry_run.unplugged.begin(), cfg.dry_run.unplugged.end(), a) ==
             cfg.dry_run.unplugged.end();
    };
    if (proto == "pca9685") {
      if (plugged(cfg.pca9685.address))
        dry->add_pca9685(static_cast<std::uint8_t>(cfg.pca9685.address));
    } else {
      for (const auto& e : cfg.escs) {
        if (plugged(e.address)) dry->add_tgy(static_cast<std::uint8_t>(e.address));
      }
    }
    owned = dry;
    transport = dry.get();
  } else if (!transport) {
    owned = std::make_shared<i2c::LinuxI2c>(proto == "pca9685" ? cfg.pca9685.bus : cfg.tgy.bus);
    transport = owned.get();
  }
  std::unique_ptr<EscBackend> b;
  if (proto == "pca9685") {
    auto pca = std::make_unique<Pca9685Backend>(*transport, cfg.pca9685, cfg.escs);
    // The OE line on the real board only (a dry run or a test's fake bus has none).
    if (cfg.pca9685.oe_line >= 0 && owned && cfg.backend != "dry_run") {
      pca->set_output_enable(gpio::open_gpiod_output(
          cfg.pca9685.oe_chip, static_cast<unsigned>(cfg.pca9685.oe_line), 1, "tiller-esc"));
    }
    b = std::move(pca);
  } else {
    b = std::make_unique<TgyBackend>(*transport, cfg.tgy, cfg.escs);
  }
  if (owned) b->keep(owned);
  if (cfg.backend == "dry_run") b->set_label("dry_run");
  return b;
}

}  // namespace tiller::esc
