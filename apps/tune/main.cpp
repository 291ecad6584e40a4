// tiller-tune: the vehicle's model identified from a log of manoeuvres, and gains proposed from
// it as a config diff to review (docs/tuning.md, "Identifying the model").
//   tiller-tune drive --log OUT [--vehicle F] [--mass-scale S --damping-scale S]
//       flies the manoeuvres (a stick script, --script) in the simulator through the pilot path;
//       on the water, tiller-stick-script plays the same script through tiller-teleop.
//   tiller-tune identify LOG [--vehicle F] [--control F] [--guidance F] [--out DIR]
//       identifies the model (lib/tune/identify.hpp), prints it against the vehicle file's
//       (times --mass-scale / --damping-scale: the simulator's), proposes gains
//       (lib/tune/propose.hpp) and writes DIR/config/... and DIR/tune.diff.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runtime/app.hpp"
#include "runtime/log.hpp"
#include "sim/sim_node.hpp"
#include "tune/drive.hpp"
#include "tune/propose.hpp"
#include "tune/record.hpp"
#include "tune/report.hpp"
#include "tune/text_edit.hpp"

namespace {

using namespace tiller;
namespace fs = std::filesystem;

int identify_command(const app::Args& a, const std::string& log) {
  const std::string vehicle = app::resolve_path(a.get("vehicle"));
  const std::string name = fs::path(vehicle).stem().string();
  const auto resolve = [&](const char* opt, const std::string& fallback) {
    return app::resolve_path(a.get(opt).empty() ? fallback : a.get(opt));
  };
  const std::string control = resolve("control", "config/control/" + name + ".yaml");
  const std::string guidance = resolve("guidance", "config/guidance/" + name + ".yaml");
  const SimVehicle sv = load_sim_vehicle_file(vehicle);
  tune::RecordStats st;
  const tune::Record r =
      tune::record_from_events(read_log(log, tune::kRecordChannels), sv.vehicle, &st);
  std::printf("%s: %d motion samples (%s), %d ESC outputs; dropped %d and %d\n", log.c_str(),
              st.motion, st.motion_channel.c_str(), st.esc, st.dropped_motion, st.dropped_esc);
  const tune::Identified id = tune::identify(r);
  SimParams scales;
  scales.mass_scale = a.get("mass-scale").empty()
                          ? 1.0
                          : app::number_option(a, "mass-scale", 0.1, 10, "a factor in [0.1, 10]");
  scales.damping_scale =
      a.get("damping-scale").empty()
          ? 1.0
          : app::number_option(a, "damping-scale", 0.1, 10, "a factor in [0.1, 10]");
  const auto model = tune::model_axes(scaled_dynamics(sv.dynamics, scales));
  const bool scaled = scales.mass_scale != 1 || scales.damping_scale != 1;
  std::fputs(tune::identify_report(id, model, sv.dynamics.thruster_time_constant_s,
                                   tune::fastest(r, id), scaled ? "simulator" : "vehicle file")
                 .c_str(),
             stdout);
  for (const auto& f : {control, guidance}) {
    if (!fs::exists(f)) {  // an ROV's tiller-rov-control file has another shape (docs/tuning.md)
      std::printf("no proposal: %s: no such file (give --control and --guidance)\n", f.c_str());
      return 0;
    }
  }
  const tune::Proposal p = tune::propose(id, vehicle, control, guidance);
  std::fputs(tune::proposal_report(p).c_str(), stdout);
  if (!a.get("out").empty()) {
    tune::write_proposal(p, a.get("out"));
    const fs::path out = a.get("out");
    std::printf("wrote %s/config/... and %s/tune.diff (apply with git apply, after review)\n",
                out.c_str(), out.c_str());
  }
  return 0;
}

int drive_command(const app::Args& a) {
  tune::DriveSpec s;
  s.vehicle_file = a.get("vehicle");
  s.script_file = a.get("script");
  s.teleop_file = a.get("teleop");
  s.log_file = a.get("log");
  if (s.log_file.empty()) throw std::runtime_error("drive: --log FILE is required");
  for (const char* k : {"mass-scale", "damping-scale"})
    if (!a.get(k).empty()) s.sim_args.insert(s.sim_args.end(), {std::string("--") + k, a.get(k)});
  const tune::DriveOutcome o = tune::drive(s);
  std::printf("%s: %.1f s simulated, %zu messages kept; %s\n", s.log_file.c_str(), o.sim_s,
              o.events.size(), o.done ? "every step flown" : o.why.c_str());
  return o.done ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const app::Spec spec{
      "tiller-tune",
      "identifies the vehicle's model from a log of manoeuvres and proposes gains",
      "",
      {{"vehicle", "FILE", "vehicle file (the reference model)", "config/vehicles/otter.yaml"},
       {"control", "FILE", "controller gains (default config/control/<vehicle>.yaml)", ""},
       {"guidance", "FILE", "guidance config (default config/guidance/<vehicle>.yaml)", ""},
       {"out", "DIR", "identify: write the proposed files and tune.diff here", ""},
       {"script", "FILE", "drive: the manoeuvres' stick script", "config/pilot/tune_usv.yaml"},
       {"teleop", "FILE", "drive: the teleop preset", "config/teleop/gamepad_blueboat.yaml"},
       {"log", "FILE", "drive: the log to write", ""},
       {"mass-scale", "S", "the simulator's mass times S (drive; identify: compare with it)", ""},
       {"damping-scale", "S", "the simulator's damping times S (as --mass-scale)", ""}},
      false,
      false,
      true,
      "drive | identify LOG",
      0,
      {{"drive", 0}, {"identify", 1}}};
  const app::Args args = app::parse(argc, argv, spec);
  return app::guarded_main(spec.program, [&] {
    if (args.positional.empty()) throw std::runtime_error("expected a command: drive or identify");
    if (args.positional[0] == "drive") return drive_command(args);
    if (args.positional.size() < 2) throw std::runtime_error("identify: expected LOG");
    return identify_command(args, args.positional[1]);
  });
}
