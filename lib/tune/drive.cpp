#include "tune/drive.hpp"

#include <filesystem>
#include <memory>
#include <regex>
#include <stdexcept>

#include "esc/esc_node.hpp"
#include "mixer/mixer_node.hpp"
#include "runtime/app.hpp"
#include "runtime/lockstep.hpp"
#include "runtime/log.hpp"
#include "sim/sim_node.hpp"
#include "sim/sim_options.hpp"
#include "teleop/stick_script.hpp"
#include "teleop/teleop_node.hpp"
#include "teleop/teleop_params.hpp"
#include "tune/record.hpp"

namespace tiller::tune {

namespace fs = std::filesystem;

namespace {

std::string existing(const std::string& given, const std::string& fallback, const char* what) {
  const std::string path = app::resolve_path(given.empty() ? fallback : given);
  if (!fs::exists(path))
    throw std::runtime_error(std::string(what) + ": " + path + ": no such file" +
                             (given.empty() ? " (the default for this vehicle)" : ""));
  return path;
}

}  // namespace

DriveOutcome drive(const DriveSpec& spec) {
  DriveOutcome out;
  out.vehicle_file = existing(spec.vehicle_file, "", "--vehicle");
  const std::string v = fs::path(out.vehicle_file).stem().string();
  out.esc_file = existing(spec.esc_file, "config/esc/" + v + "_sim.yaml", "--esc");
  out.mixer_file = existing(spec.mixer_file, "config/mixer/" + v + ".yaml", "--mixer");
  const std::string sim_file = existing(spec.sim_file, "", "--sim");

  std::vector<std::string> args = {"--vehicle", out.vehicle_file};
  args.insert(args.end(), spec.sim_args.begin(), spec.sim_args.end());
  const SimOverrides so = sim_overrides(args);
  const auto sroot = config::Value::load_file(sim_file);
  SimParams sp = load_sim_params(sroot);
  sroot.check_all_used();
  apply(so, sp);
  SimNode sim(sp, load_sim_vehicle_file(out.vehicle_file));
  EscNode esc(out.esc_file);
  MixerNode mixer(out.mixer_file);
  TeleopNode teleop(load_teleop_file(existing(spec.teleop_file, "", "--teleop")));
  StickScriptNode script(load_stick_script_file(existing(spec.script_file, "", "--script")));
  script.on_stick([&](const joystick_state_t& s, TimeUs now) { teleop.feed(s, now); });

  LockstepExecutor ex(0);
  for (Node* n : {static_cast<Node*>(&sim), static_cast<Node*>(&esc), static_cast<Node*>(&mixer),
                  static_cast<Node*>(&teleop), static_cast<Node*>(&script)})
    ex.add(*n);
  std::unique_ptr<LogWriter> log;
  if (!spec.log_file.empty()) {
    std::error_code ec;
    fs::remove(spec.log_file, ec);  // lcm::LogFile appends: the log holds this run only
    log = std::make_unique<LogWriter>(spec.log_file);
  }
  const std::regex kept(kRecordChannels);
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    if (log) log->write(ch, d, n, t);
    if (std::regex_match(ch, kept))
      out.events.push_back(Event{ch, t, std::vector<std::uint8_t>(d, d + n)});
  });
  const TimeUs limit = from_seconds(spec.time_limit_s);
  TimeUs t = 0;
  while (t < limit && !script.done()) {
    t += 100'000;
    ex.run_until(t);
  }
  out.sim_s = to_seconds(t);
  out.done = script.done() && !script.failed();
  out.why = script.failed()  ? script.why()
            : !script.done() ? "the script did not end within " +
                                   std::to_string(static_cast<int>(spec.time_limit_s)) + " s"
                             : "";
  return out;
}

}  // namespace tiller::tune
