// tiller-mission: publishes a path from a YAML, CSV or QGroundControl .plan mission file
// (TILLER_PATH; a mission with items flies leg by leg, docs/missions.md) and the
// waypointing mode (TILLER_MODE), repeated every --repeat-s seconds until stopped (same path_id:
// the follower does not restart); sends ONE arm request, and ONE operator START
// (TILLER_MISSION_COMMAND) once the vehicle is armed (docs/safety.md). --repeat-s 0 publishes
// once and exits after the START (or after --start-wait-s without arming).
// --start-std-m M (and --start-settle-s S) waits, publishing nothing, until TILLER_ODOMETRY is
// valid with its horizontal position 1-sigma <= M m, held for S s (mission/start_gate.hpp).
// --datum-from-vehicle: a mission in lat/lon waits for TILLER_DATUM and is converted about it.
// --command pause|resume|abort|release sends that operator command (and, for release, a disarm
// request) and exits. `tiller-mission survey POLYGON.geojson --spacing 5 --angle 30` writes a
// lawnmower plan (survey_cmd.cpp). It has no config file (--config is refused): the mission is
// --mission FILE.
#include <tiller/arm_request_t.hpp>
#include <tiller/mission_command_t.hpp>

#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <utility>

#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mission/start_gate_options.hpp"
#include "runtime/app.hpp"
#include "runtime/channels.hpp"
#include "runtime/live.hpp"
#include "survey_cmd.hpp"

namespace {

// Stops the executor once the mission node has sent its START, or at a deadline.
class StopWhenStarted : public tiller::Node {
 public:
  StopWhenStarted(const tiller::mission::MissionNode& m, tiller::LiveExecutor& ex,
                  tiller::TimeUs deadline)
      : Node("mission-once", 50'000), m_(m), ex_(ex), deadline_(deadline) {}
  void on_tick(tiller::TimeUs now) override {
    if (m_.started() || now >= deadline_) ex_.stop();
  }

 private:
  const tiller::mission::MissionNode& m_;
  tiller::LiveExecutor& ex_;
  tiller::TimeUs deadline_;
};

template <class Msg>
void send(tiller::LiveExecutor& ex, const char* channel, const Msg& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  ex.publish_raw(channel, buf.data(), static_cast<int>(buf.size()));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tiller;
  if (argc >= 2 && std::string(argv[1]) == "survey") return survey_main(argc, argv);
  app::Spec spec{
      "tiller-mission",
      "Publishes a mission's path and the waypointing mode, one arm request and, once armed, "
      "the operator's START; or sends one operator command (--command). "
      "tiller-mission survey POLYGON.geojson [--spacing M] [--angle DEG] [--vehicle FILE] "
      "[--turn-radius-m R] [--home LAT,LON] [--out FILE.plan] writes a lawnmower plan.",
      "",
      {{"mission", "FILE", "mission file (.yaml, .csv or a QGroundControl .plan)",
        "config/missions/default.yaml"},
       {"path-id", "N",
        "path id, a whole number >= 0 (default: the start time in us, so each run is a new path)",
        ""},
       {"repeat-s", "S", "repeat period, s >= 0; 0 = publish once and exit", "1"},
       {"start-wait-s", "S", "with --repeat-s 0: how long to wait for arming, s", "3"},
       {"no-arm", "", "do not send the arm request (START still waits for arming)", ""},
       {"datum-from-vehicle", "",
        "a mission in lat/lon waits for the vehicle's datum (TILLER_DATUM from tiller-nav) and "
        "is converted about it, not about its home",
        ""},
       {"command", "NAME", "send pause, resume, abort or release and exit", ""}},
      false};  // no config file: the mission is --mission FILE
  for (auto& o : mission::start_gate_options()) spec.options.push_back(std::move(o));
  const auto args = app::parse(argc, argv, spec);

  return app::guarded_main("tiller-mission", [&] {
    const std::string command = args.get("command");
    if (!command.empty()) {
      mission_command_t c{};
      if (command == "pause") {
        c.command = mission_command_t::PAUSE;
      } else if (command == "resume") {
        c.command = mission_command_t::RESUME;
      } else if (command == "abort") {
        c.command = mission_command_t::ABORT;
      } else if (command == "release") {
        c.command = mission_command_t::RELEASE;
      } else {
        std::cerr << "tiller-mission: --command: expected pause, resume, abort or release, got '"
                  << command << "'\n";
        return 2;
      }
      LiveExecutor ex(args.lcm_url, args.auth);
      c.utime = wall_time_us();
      c.command_id = c.utime;
      c.source = "tiller-mission";
      send(ex, channels::kMissionCommand, c);
      if (c.command == mission_command_t::RELEASE) {
        arm_request_t a{};
        a.utime = wall_time_us();
        a.arm = false;
        a.source = "tiller-mission (release)";
        send(ex, channels::kArmRequest, a);
      }
      std::cout << "tiller-mission: sent " << command << " (id " << c.command_id << ")\n";
      return 0;
    }
    // Numbers first, whole strings only; a bad value names the flag and what was expected.
    const double repeat =
        app::number_option(args, "repeat-s", 0, std::numeric_limits<double>::infinity(),
                           "a number of seconds >= 0 (0 = publish once)");
    const double wait =
        app::number_option(args, "start-wait-s", 0, 3600, "a number of seconds in [0, 3600]");
    std::int64_t id =
        args.get("path-id").empty()
            ? -1
            : app::integer_option(args, "path-id", 0, INT64_MAX, "a whole number >= 0 (int64)");
    const mission::StartGateParams gate = mission::start_gate_params(args);
    const auto m = mission::load_mission_file(args.get("mission"));
    if (id < 0) id = wall_time_us();
    std::cout << "tiller-mission: " << m.name << ": " << m.waypoints.size()
              << " waypoints, path_id " << id << "\n";
    LiveExecutor ex(args.lcm_url, args.auth);
    // Once: the first tick publishes everything; the period is long enough not to repeat.
    const TimeUs period = repeat > 0 ? from_seconds(repeat) : from_seconds(wait + 3600);
    if (gate.enabled)
      std::cout << "tiller-mission: waiting for the estimate: position 1-sigma <= "
                << gate.max_position_std_m << " m for " << gate.settle_s << " s\n";
    const bool from_vehicle = args.flag("datum-from-vehicle");
    if (from_vehicle && m.geodetic())
      std::cout << "tiller-mission: waiting for the vehicle's datum (TILLER_DATUM)\n";
    mission::MissionNode node(m, id, period, !args.flag("no-arm"), gate, from_vehicle);
    ex.add(node);
    if (repeat > 0) return ex.run();
    StopWhenStarted stopper(node, ex, wall_time_us() + from_seconds(wait));
    ex.add(stopper);
    const int rc = ex.run();
    if (!node.started() && node.began_at() < 0)
      std::cerr << "tiller-mission: the estimate was not ready within " << wait
                << " s: nothing sent\n";
    else if (!node.started())
      std::cerr << "tiller-mission: not armed within " << wait << " s: no START sent\n";
    return rc;
  });
}
