// CockpitNode without sockets: the token rule, the gamepad's centring and deadman, state frames
// (latest value per channel, health), commands and mission files, on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/thruster_test_t.hpp>

#include "cockpit/cockpit_node.hpp"
#include "cockpit/files.hpp"
#include "runtime/channels.hpp"
#include "runtime/event.hpp"

namespace tiller::cockpit {
namespace {

using nlohmann::json;
const std::string kToken = "0123456789abcdef0123456789abcdef";

class CollectBus : public Bus {
 public:
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    events.push_back(Event{std::string(channel), 0, std::vector<std::uint8_t>(data, data + size)});
  }
  std::vector<Event> events;
  template <class Msg>
  std::vector<Msg> on(const std::string& ch) const {
    std::vector<Msg> out;
    for (const auto& e : events) {
      if (e.channel != ch) continue;
      Msg m;
      m.decode(e.data.data(), 0, static_cast<int>(e.data.size()));
      out.push_back(m);
    }
    return out;
  }
};

CockpitParams params() {
  CockpitParams p;
  p.processes = {"sim", "mixer"};
  p.axes = {{3, 0, -1.0, 0.1, 0.3, 1.0}, {0, 5, 1.0, 0.1, 0.0, 1.0}};  // surge, yaw
  return p;
}

struct Rig {
  Rig() : node(params(), kToken, &load_mission_text) {
    node.attach(&bus);
    node.set_sink([this](int c, const std::string& s) { frames.push_back({c, json::parse(s)}); });
  }
  void send(int client, json j, TimeUs now, bool with_token = true) {
    if (with_token) j["token"] = kToken;
    node.command(client, j.dump(), now);
  }
  json last_reply() const {
    for (auto it = frames.rbegin(); it != frames.rend(); ++it)
      if (it->second["type"] == "reply") return it->second;
    return {};
  }
  json last_state() const {
    for (auto it = frames.rbegin(); it != frames.rend(); ++it)
      if (it->second["type"] == "state") return it->second;
    return {};
  }
  void pad(int client, double surge_axis, double yaw_axis, TimeUs now) {
    send(client,
         {{"type", "gamepad"}, {"connected", true}, {"axes", {yaw_axis, 0.0, 0.0, surge_axis}}},
         now);
  }
  std::vector<manual_demand_t> demands() const {
    return bus.on<manual_demand_t>(channels::kManualDemand);
  }
  CollectBus bus;
  CockpitNode node;
  std::vector<std::pair<int, json>> frames;
};

TEST(CockpitNode, CommandWithoutOrWithWrongTokenIsRefusedAndCounted) {
  Rig r;
  r.send(1, {{"type", "arm"}, {"arm", true}, {"confirm", true}}, 1'000, false);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  r.send(1, {{"type", "arm"}, {"arm", true}, {"confirm", true}, {"token", kToken + "0"}}, 2'000,
         false);
  std::string wrong = kToken;
  wrong[5] = 'X';
  r.send(1, {{"type", "arm"}, {"arm", true}, {"confirm", true}, {"token", wrong}}, 3'000, false);
  EXPECT_EQ(r.node.counter_value("rejected.command.token"), 3);
  EXPECT_EQ(r.node.rejected(), 3);
  EXPECT_TRUE(r.bus.on<arm_request_t>(channels::kArmRequest).empty());
  // The gamepad too: no demand without the token.
  r.send(1, {{"type", "gamepad"}, {"axes", {0.0, 0.0, 0.0, 0.0}}}, 4'000, false);
  EXPECT_TRUE(r.demands().empty());
  EXPECT_EQ(r.node.counter_value("rejected.command.token"), 4);
  // With it: one arm request, from "cockpit".
  r.send(1, {{"type", "arm"}, {"arm", true}, {"confirm", true}, {"id", 7}}, 5'000);
  const auto arms = r.bus.on<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(arms.size(), 1u);
  EXPECT_TRUE(arms[0].arm);
  EXPECT_EQ(arms[0].source, "cockpit");
  EXPECT_EQ(r.last_reply()["id"], 7);
  EXPECT_TRUE(r.last_reply()["ok"].get<bool>());
}

TEST(CockpitNode, ArmingNeedsConfirmDisarmDoesNot) {
  Rig r;
  r.send(1, {{"type", "arm"}, {"arm", true}}, 1'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  EXPECT_TRUE(r.bus.on<arm_request_t>(channels::kArmRequest).empty());
  r.send(1, {{"type", "arm"}, {"arm", false}}, 2'000);
  ASSERT_EQ(r.bus.on<arm_request_t>(channels::kArmRequest).size(), 1u);
  EXPECT_FALSE(r.bus.on<arm_request_t>(channels::kArmRequest)[0].arm);
}

TEST(CockpitNode, GamepadIsNeutralAndInvalidUntilCentredThenShaped) {
  Rig r;
  r.pad(1, -1.0, 0.0, 10'000);  // stick held forward at the start: not centred
  r.pad(1, -1.0, 0.0, 60'000);
  auto d = r.demands();
  ASSERT_EQ(d.size(), 2u);
  for (const auto& m : d) {
    EXPECT_FALSE(m.valid);
    EXPECT_EQ(m.demand[0], 0.0);
  }
  r.pad(1, 0.05, 0.0, 110'000);  // inside the deadzone: centred
  r.pad(1, -0.5, 0.0, 160'000);  // half forward
  d = r.demands();
  ASSERT_EQ(d.size(), 4u);
  EXPECT_TRUE(d[2].valid);
  EXPECT_EQ(d[2].demand[0], 0.0);
  EXPECT_TRUE(d[3].valid);
  // deadzone 0.1, expo 0.3: s = (0.5 - 0.1) / 0.9 = 0.444444; y = 0.7 s + 0.3 s^3 = 0.337449;
  // sign -1 on an axis at -0.5: +0.337449 surge.
  EXPECT_NEAR(d[3].demand[0], 0.337449, 1e-6);
  for (int i = 1; i < 6; ++i) EXPECT_EQ(d[3].demand[i], 0.0);
  EXPECT_EQ(r.node.pilot_client(), 1);
}

TEST(CockpitNode, AnAxisNeverReportedIsNotCentred) {
  Rig r;
  r.send(1, {{"type", "gamepad"}, {"axes", {0.0, 0.0}}}, 10'000);  // axis 3 missing
  ASSERT_EQ(r.demands().size(), 1u);
  EXPECT_FALSE(r.demands()[0].valid);
  EXPECT_FALSE(r.node.pilot_centred());
}

TEST(CockpitNode, SilenceClosedSocketHiddenPageAndBadValuesGiveNeutralAtOnce) {
  Rig r;
  r.pad(1, 0.0, 0.0, 10'000);
  r.pad(1, -1.0, 0.0, 60'000);
  ASSERT_TRUE(r.demands().back().valid);
  // Deadman: the page stops sending; the tick after timeout_s (0.5 s) sends neutral, invalid.
  r.node.tick(550'000);
  EXPECT_TRUE(r.demands().back().valid);  // 490 ms: not yet
  r.node.tick(600'000);
  EXPECT_FALSE(r.demands().back().valid);
  EXPECT_EQ(r.demands().back().demand[0], 0.0);
  EXPECT_EQ(r.node.counter_value("pilot.lost.timeout"), 1);
  // Back with the stick still held: stays neutral until centred again.
  r.pad(1, -1.0, 0.0, 800'000);
  EXPECT_FALSE(r.demands().back().valid);
  r.pad(1, 0.0, 0.0, 850'000);
  r.pad(1, -1.0, 0.0, 900'000);
  EXPECT_TRUE(r.demands().back().valid);
  // The socket closes: neutral at once, no tick needed.
  std::size_t n = r.demands().size();
  r.node.client_closed(1, 910'000);
  ASSERT_EQ(r.demands().size(), n + 1);
  EXPECT_FALSE(r.demands().back().valid);
  EXPECT_EQ(r.node.pilot_client(), -1);
  // A hidden page says connected: false.
  r.pad(2, 0.0, 0.0, 1'000'000);
  r.pad(2, -1.0, 0.0, 1'050'000);
  ASSERT_TRUE(r.demands().back().valid);
  r.send(2, {{"type", "gamepad"}, {"connected", false}}, 1'060'000);
  EXPECT_FALSE(r.demands().back().valid);
  EXPECT_EQ(r.node.counter_value("pilot.lost.released"), 1);
  // A value outside [-1, 1]: neutral at once, counted.
  r.pad(2, 0.0, 0.0, 1'100'000);
  r.pad(2, -1.0, 0.0, 1'150'000);
  ASSERT_TRUE(r.demands().back().valid);
  r.send(2, {{"type", "gamepad"}, {"axes", {0.0, 0.0, 0.0, -1.5}}}, 1'160'000);
  EXPECT_FALSE(r.demands().back().valid);
  EXPECT_EQ(r.node.counter_value("rejected.gamepad.value"), 2);  // the pilot loss and the drop
  // shutdown() (SIGINT/SIGTERM) with a pilot: neutral, invalid.
  r.pad(2, 0.0, 0.0, 1'200'000);
  r.pad(2, -1.0, 0.0, 1'250'000);
  r.node.shutdown(1'260'000);
  EXPECT_FALSE(r.demands().back().valid);
}

TEST(CockpitNode, OnePilotAtATime) {
  Rig r;
  r.pad(1, 0.0, 0.0, 10'000);
  const std::size_t n = r.demands().size();
  r.pad(2, 0.0, 0.0, 20'000);
  EXPECT_EQ(r.demands().size(), n);
  EXPECT_EQ(r.node.counter_value("rejected.gamepad.other_pilot"), 1);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
}

TEST(CockpitNode, StateFramesCarryTheLatestValueOfChangedChannelsAndHealth) {
  Rig r;
  odometry_t o{};
  o.position[0] = 1.5;
  for (int i = 0; i < 3; ++i) {
    o.utime = i;
    o.position[1] = i;
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(o.getEncodedSize()));
    o.encode(buf.data(), 0, static_cast<int>(buf.size()));
    r.node.deliver(channels::kOdometry, buf.data(), static_cast<int>(buf.size()), 10'000 + i);
  }
  heartbeat_t hb{};
  hb.process = "mixer";
  hb.state = heartbeat_t::STATE_DEGRADED;
  hb.status = "disarmed";
  std::vector<std::uint8_t> hbuf(static_cast<std::size_t>(hb.getEncodedSize()));
  hb.encode(hbuf.data(), 0, static_cast<int>(hbuf.size()));
  r.node.deliver("TILLER_HEARTBEAT_MIXER", hbuf.data(), static_cast<int>(hbuf.size()), 20'000);
  r.node.tick(50'000);
  json s = r.last_state();
  ASSERT_TRUE(s["msgs"].contains("TILLER_ODOMETRY"));
  EXPECT_EQ(s["msgs"]["TILLER_ODOMETRY"]["msg"]["position"][1], 2.0);  // the latest of three
  EXPECT_EQ(s["msgs"]["TILLER_ODOMETRY"]["rx"], 10'002);
  EXPECT_EQ(s["health"][0]["process"], "sim");
  EXPECT_EQ(s["health"][0]["state"], "SILENT");
  EXPECT_EQ(s["health"][1]["state"], "DEGRADED");
  EXPECT_EQ(s["health"][1]["status"], "disarmed");
  r.node.tick(100'000);
  s = r.last_state();
  EXPECT_FALSE(s["msgs"].contains("TILLER_ODOMETRY"));  // unchanged: not sent again
  r.node.tick(3'000'000);
  EXPECT_EQ(r.last_state()["health"][1]["state"], "DEGRADED");  // 2.98 s old
  r.node.tick(3'050'000);                                       // 3.03 s > silent_after_s
  EXPECT_EQ(r.last_state()["health"][1]["state"], "SILENT");
  // A new client gets hello and the full snapshot (odometry included).
  r.node.client_opened(5, 3'200'000);
  ASSERT_GE(r.frames.size(), 2u);
  EXPECT_EQ(r.frames[r.frames.size() - 2].first, 5);
  EXPECT_EQ(r.frames[r.frames.size() - 2].second["type"], "hello");
  EXPECT_EQ(r.frames.back().second["type"], "snapshot");
  EXPECT_TRUE(r.frames.back().second["msgs"].contains("TILLER_ODOMETRY"));
  EXPECT_EQ(r.frames[r.frames.size() - 2].second["constants"]["thruster_command_t"]["GATE_ACTIVE"],
            2);
  // A bad odometry is dropped and counted, the last good one stays.
  o.orientation[2] = 4.0;
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(o.getEncodedSize()));
  o.encode(buf.data(), 0, static_cast<int>(buf.size()));
  r.node.deliver(channels::kOdometry, buf.data(), static_cast<int>(buf.size()), 3'300'000);
  EXPECT_EQ(r.node.counter_value("rejected.odometry.check"), 1);
}

// Issue 30: the vehicle's arm state, its reason and the station in control reach the page in
// the next state frame (the cockpit's period, 50 ms), whatever its stamp (here 0.7 s behind the
// cockpit's clock); the cockpit's arm requests carry its nonce, station and a takeover.
TEST(CockpitNode, RefusalReasonAndControllerReachThePageWithTheNonceOnArming) {
  CockpitParams p = params();
  p.station = "cockpit@topside";
  CollectBus bus;
  CockpitNode node(p, kToken, &load_mission_text);
  node.attach(&bus);
  std::vector<json> frames;
  node.set_sink([&](int, const std::string& f) { frames.push_back(json::parse(f)); });
  arm_state_t a{};
  a.utime = 1'000'000 - 700'000;
  a.armed = true;
  a.session = 3;
  a.boot_nonce = 4242;
  a.controller = "A";
  a.reason =
      "arm refused (asked by cockpit at station cockpit@topside): another station in "
      "control: A";
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(a.getEncodedSize()));
  a.encode(buf.data(), 0, static_cast<int>(buf.size()));
  node.deliver(channels::kArmState, buf.data(), static_cast<int>(buf.size()), 1'000'000);
  node.tick(1'050'000);
  json st;
  for (auto it = frames.rbegin(); it != frames.rend() && st.is_null(); ++it)
    if ((*it)["type"] == "state") st = *it;
  ASSERT_TRUE(st["msgs"].contains("TILLER_ARM_STATE")) << st.dump();
  const json& m = st["msgs"]["TILLER_ARM_STATE"]["msg"];
  EXPECT_EQ(m["armed"], true);
  EXPECT_EQ(m["controller"], "A");
  EXPECT_EQ(m["reason"], a.reason);
  json cmd = {
      {"type", "arm"}, {"arm", true}, {"confirm", true}, {"takeover", true}, {"token", kToken}};
  node.command(1, cmd.dump(), 1'100'000);
  const auto arms = bus.on<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(arms.size(), 1u);
  EXPECT_EQ(arms[0].boot_nonce, 4242);
  EXPECT_EQ(arms[0].station, "cockpit@topside");
  EXPECT_TRUE(arms[0].takeover);
  node.attach(nullptr);
}

// Issue 31: the GNSS fix (its type, RTK included, satellites, HDOP, 1-sigma) reaches the page.
TEST(CockpitNode, TheGnssFixReachesThePage) {
  Rig r;
  gnss_fix_t g{};
  g.utime = 10'000;
  g.fix_type = gnss_fix_t::FIX_RTK_FIXED;
  g.satellites = 17;
  g.latitude = 59.437;
  g.longitude = 10.6612;
  g.hdop = 0.7;
  g.position_std[0] = g.position_std[1] = 0.02;
  g.accuracy_source = gnss_fix_t::ACCURACY_RECEIVER;
  g.device = "/dev/ttyACM0";
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(g.getEncodedSize()));
  g.encode(buf.data(), 0, static_cast<int>(buf.size()));
  r.node.deliver(channels::kGnss, buf.data(), static_cast<int>(buf.size()), 10'000);
  r.node.tick(50'000);
  const json s = r.last_state();
  ASSERT_TRUE(s["msgs"].contains("TILLER_GNSS")) << s.dump();
  EXPECT_EQ(s["msgs"]["TILLER_GNSS"]["msg"]["fix_type"], gnss_fix_t::FIX_RTK_FIXED);
  EXPECT_EQ(s["msgs"]["TILLER_GNSS"]["msg"]["satellites"], 17);
  EXPECT_EQ(s["msgs"]["TILLER_GNSS"]["msg"]["hdop"], 0.7);
}

TEST(CockpitNode, MissionLoadStartAndErrorsWithLineAndKey) {
  Rig r;
  r.send(1,
         {{"type", "mission_load"},
          {"name", "box.yaml"},
          {"text", "name: box\nwaypoints:\n  - [0, 0]\n  - [10, 0]\n  - [10, 10]\n"}},
         1'000'000);
  ASSERT_TRUE(r.last_reply()["ok"].get<bool>()) << r.last_reply().dump();
  auto paths = r.bus.on<path_t>(channels::kPath);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].n_waypoints, 3);
  EXPECT_EQ(paths[0].waypoints[1].position[0], 10.0);
  const auto modes = r.bus.on<controller_mode_t>(channels::kMode);
  ASSERT_EQ(modes.size(), 1u);
  EXPECT_EQ(modes[0].mode, controller_mode_t::WAYPOINTING);
  // Re-sent every path_repeat_s with the same id.
  r.node.tick(2'000'000);
  paths = r.bus.on<path_t>(channels::kPath);
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[1].path_id, paths[0].path_id);
  // Start and pause: two operator commands with new, growing ids.
  r.send(1, {{"type", "mission"}, {"command", "start"}}, 2'100'000);
  r.send(1, {{"type", "mission"}, {"command", "pause"}}, 2'100'000);
  const auto cmds = r.bus.on<mission_command_t>(channels::kMissionCommand);
  ASSERT_EQ(cmds.size(), 2u);
  EXPECT_EQ(cmds[0].command, mission_command_t::START);
  EXPECT_EQ(cmds[1].command, mission_command_t::PAUSE);
  EXPECT_GT(cmds[1].command_id, cmds[0].command_id);
  EXPECT_GT(cmds[0].command_id, paths[0].path_id);
  // A broken file: refused, the reply names the uploaded file, the line and the key.
  r.send(1,
         {{"type", "mission_load"},
          {"name", "bad.yaml"},
          {"text", "name: bad\nwaypoints:\n  - [0, x]\n"}},
         3'000'000);
  const json rep = r.last_reply();
  EXPECT_FALSE(rep["ok"].get<bool>());
  const std::string err = rep["error"];
  EXPECT_NE(err.find("bad.yaml:3"), std::string::npos) << err;
  EXPECT_NE(err.find("waypoints[0]"), std::string::npos) << err;
  EXPECT_EQ(err.find("tiller-cockpit-"), std::string::npos) << err;  // not the temporary copy
  EXPECT_EQ(r.node.counter_value("rejected.mission.file"), 1);
  r.send(1, {{"type", "mission_load"}, {"name", "x.txt"}, {"text", "1,2"}}, 3'100'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  // Abort stops the repeats.
  r.send(1, {{"type", "mission"}, {"command", "abort"}}, 3'200'000);
  const std::size_t n = r.bus.on<path_t>(channels::kPath).size();
  r.node.tick(5'000'000);
  EXPECT_EQ(r.bus.on<path_t>(channels::kPath).size(), n);
}

template <class Msg>
void deliver(CockpitNode& node, const char* channel, const Msg& m, TimeUs now) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  node.deliver(channel, buf.data(), static_cast<int>(buf.size()), now);
}

std::string file_text(const std::string& rel) {
  std::ifstream in(std::string(TILLER_SOURCE_DIR) + "/" + rel);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A QGroundControl plan uploaded from the page: in lat/lon, so refused until the vehicle's datum
// is known; then converted about that datum, flown leg by leg as tiller-mission flies it (the
// speeds before each leg's path, the next leg when the follower says this one is complete, the
// 10 s loiter timed), and its points, home and fence sent to every page's map.
TEST(CockpitNode, AnUploadedPlanWithItemsIsFlownLegByLegAndDrawn) {
  Rig r;
  const std::string plan = file_text("config/missions/harbour.plan");
  r.send(1, {{"type", "mission_load"}, {"name", "harbour.plan"}, {"text", plan}}, 100'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  EXPECT_NE(r.last_reply()["error"].get<std::string>().find("datum"), std::string::npos)
      << r.last_reply().dump();
  EXPECT_TRUE(r.bus.on<path_t>(channels::kPath).empty());

  datum_t d{};  // the plan's home: its metres are plan_flight_test's
  d.utime = 200'000;
  d.latitude = 63.44;
  d.longitude = 10.4;
  d.altitude = 2.0;
  deliver(r.node, channels::kDatum, d, 200'000);
  odometry_t o{};
  o.utime = 200'000;
  o.valid = odometry_t::VALID_POSITION;
  deliver(r.node, channels::kOdometry, o, 200'000);
  r.send(1, {{"type", "mission_load"}, {"name", "harbour.plan"}, {"text", plan}}, 300'000);
  ASSERT_TRUE(r.last_reply()["ok"].get<bool>()) << r.last_reply().dump();
  EXPECT_NE(r.last_reply()["detail"].get<std::string>().find("7 items"), std::string::npos)
      << r.last_reply().dump();
  // The map's frame: every item's point about the datum, home, the inclusion fence.
  json mf;
  for (const auto& f : r.frames)
    if (f.second["type"] == "mission") mf = f.second;
  ASSERT_FALSE(mf.is_null());
  // Sent once per load, so queued for every page, never latest-value: a state frame the next tick
  // writes before the sender thread runs would replace it (the browser test's map once stayed
  // empty so, under load).
  for (const auto& f : r.frames)
    if (f.second["type"] == "mission") {
      EXPECT_EQ(f.first, CockpitNode::kEveryClient);
    }
  ASSERT_EQ(mf["points"].size(), 5u);  // 4 waypoints and loiter, and home for the return
  EXPECT_NEAR(mf["points"][0][0].get<double>(), 30.0, 0.01);
  EXPECT_NEAR(mf["points"][0][1].get<double>(), 0.0, 0.01);
  EXPECT_NEAR(mf["points"][2][0].get<double>(), 10.0, 0.01);  // the loiter (10, 25)
  EXPECT_NEAR(mf["points"][2][1].get<double>(), 25.0, 0.01);
  EXPECT_NEAR(mf["home"][0].get<double>(), 0.0, 1e-6);
  ASSERT_EQ(mf["fence"].size(), 1u);
  EXPECT_TRUE(mf["fence"][0]["inclusion"].get<bool>());
  EXPECT_EQ(mf["fence"][0]["polygon"].size(), 4u);
  EXPECT_NEAR(mf["fence"][0]["polygon"][0][0].get<double>(), -15.0, 0.05);
  EXPECT_NEAR(mf["datum"]["lat"].get<double>(), 63.44, 1e-12);

  // Leg 1: from the vehicle (0, 0) to the loiter point, at 1.0 m/s; its speeds before its path.
  auto paths = r.bus.on<path_t>(channels::kPath);
  auto speeds = r.bus.on<path_speed_t>(channels::kPathSpeed);
  ASSERT_EQ(paths.size(), 1u);
  ASSERT_EQ(speeds.size(), 1u);
  const std::int64_t leg1 = paths[0].path_id;
  EXPECT_EQ(speeds[0].path_id, leg1);
  ASSERT_EQ(paths[0].n_waypoints, 4);
  EXPECT_NEAR(paths[0].waypoints[0].position[0], 0.0, 1e-9);
  EXPECT_NEAR(paths[0].waypoints[3].position[0], 10.0, 0.01);
  EXPECT_NEAR(paths[0].waypoints[3].position[1], 25.0, 0.01);
  EXPECT_EQ(speeds[0].speed[0], 1.0);
  std::size_t first_speed = 0, first_path = 0;
  for (std::size_t i = 0; i < r.bus.events.size(); ++i) {
    if (!first_speed && r.bus.events[i].channel == channels::kPathSpeed) first_speed = i + 1;
    if (!first_path && r.bus.events[i].channel == channels::kPath) first_path = i + 1;
  }
  EXPECT_LT(first_speed, first_path);
  // Progress on another path or not complete: nothing; complete: the loiter's 10 s, then leg 2.
  path_progress_t pr{};
  pr.utime = 20'000'000;
  pr.path_id = leg1 + 5;
  pr.complete = true;
  deliver(r.node, channels::kPathProgress, pr, 20'000'000);
  pr.path_id = leg1;
  pr.complete = false;
  deliver(r.node, channels::kPathProgress, pr, 20'000'000);
  pr.complete = true;
  deliver(r.node, channels::kPathProgress, pr, 20'000'000);
  for (TimeUs t = 20'050'000; t < 29'950'000; t += 50'000) r.node.tick(t);
  paths = r.bus.on<path_t>(channels::kPath);
  for (const auto& p : paths) EXPECT_EQ(p.path_id, leg1);  // repeats of leg 1 only
  for (TimeUs t = 29'950'000; t <= 30'200'000; t += 50'000) r.node.tick(t);
  paths = r.bus.on<path_t>(channels::kPath);
  EXPECT_EQ(paths.back().path_id, leg1 + 1);
  EXPECT_NEAR(paths.back().waypoints[0].position[0], 10.0, 0.01);  // from the loiter point
  EXPECT_NEAR(paths.back().waypoints[0].position[1], 25.0, 0.01);
  EXPECT_EQ(r.bus.on<path_speed_t>(channels::kPathSpeed).back().speed[0], 1.5);
  // A page that opens now is shown the plan after its hello.
  const std::size_t before = r.frames.size();
  r.node.client_opened(2, 30'300'000);
  ASSERT_GE(r.frames.size(), before + 2);
  EXPECT_EQ(r.frames[before].second["type"], "hello");
  EXPECT_EQ(r.frames[before + 1].second["type"], "mission");
  // Abort ends it: no more legs or repeats.
  r.send(1, {{"type", "mission"}, {"command", "abort"}}, 30'400'000);
  const std::size_t n = r.bus.on<path_t>(channels::kPath).size();
  deliver(r.node, channels::kPathProgress, pr, 31'000'000);
  for (TimeUs t = 30'450'000; t < 40'000'000; t += 50'000) r.node.tick(t);
  EXPECT_EQ(r.bus.on<path_t>(channels::kPath).size(), n);
}

// With start_gate, a mission start is refused while the estimate is not good enough, saying why;
// once the odometry's 1-sigma is within the limit the same command goes out.
TEST(CockpitNode, StartWaitsForTheEstimateWithAStartGate) {
  CockpitParams p = params();
  p.start_gate.enabled = true;
  p.start_gate.max_position_std_m = 0.3;
  CollectBus bus;
  CockpitNode node(p, kToken, &load_mission_text);
  node.attach(&bus);
  json reply;
  node.set_sink([&](int, const std::string& s) {
    const json j = json::parse(s);
    if (j["type"] == "reply") reply = j;
  });
  const auto odom = [&](double var, TimeUs t) {
    odometry_t o{};
    o.utime = t;
    o.valid = 7;  // position, velocity, attitude
    o.n_pose_cov = 36;
    o.pose_covariance.assign(36, 0.0);
    o.pose_covariance[0] = o.pose_covariance[7] = var;
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(o.getEncodedSize()));
    o.encode(buf.data(), 0, static_cast<int>(buf.size()));
    node.deliver(channels::kOdometry, buf.data(), static_cast<int>(buf.size()), t);
  };
  const auto start = [&](TimeUs t) {
    json j = {{"type", "mission"}, {"command", "start"}, {"token", kToken}};
    node.command(1, j.dump(), t);
  };
  start(100'000);  // no odometry at all
  EXPECT_FALSE(reply["ok"].get<bool>());
  EXPECT_EQ(reply["error"], "start refused: the estimate is not ready: no odometry yet");
  odom(0.25, 200'000);  // 0.5 m
  start(200'000);
  EXPECT_EQ(reply["error"],
            "start refused: the estimate is not ready: position 1-sigma 0.50 m > 0.30 m");
  EXPECT_TRUE(bus.on<mission_command_t>(channels::kMissionCommand).empty());
  EXPECT_EQ(node.counter_value("rejected.mission.not_ready"), 2);
  odom(0.04, 300'000);  // 0.2 m
  start(300'000);
  EXPECT_TRUE(reply["ok"].get<bool>()) << reply.dump();
  const auto cmds = bus.on<mission_command_t>(channels::kMissionCommand);
  ASSERT_EQ(cmds.size(), 1u);
  EXPECT_EQ(cmds[0].command, mission_command_t::START);
}

// Every controller_mode_t constant can be asked for by name, the ROV modes included.
TEST(CockpitNode, ModeCommandsCoverTheRovModes) {
  Rig r;
  r.send(1, {{"type", "mode"}, {"mode", "DEPTH_HOLD"}}, 1'000);
  r.send(1, {{"type", "mode"}, {"mode", "POSITION_HOLD"}}, 2'000);
  r.send(1, {{"type", "mode"}, {"mode", "WAYPOINTING"}, {"is_translation", true}}, 3'000);
  const auto modes = r.bus.on<controller_mode_t>(channels::kMode);
  ASSERT_EQ(modes.size(), 3u);
  EXPECT_EQ(modes[0].mode, 4);  // controller_mode_t.lcm: DEPTH_HOLD = 4
  EXPECT_EQ(modes[1].mode, 8);  // POSITION_HOLD = 8
  EXPECT_EQ(modes[2].mode, 2);  // WAYPOINTING = 2
  EXPECT_TRUE(modes[2].is_translation);
  EXPECT_EQ(modes[0].source, "cockpit");
  EXPECT_EQ(r.node.counter_value("rejected.command.malformed"), 0);
}

TEST(CockpitNode, MalformedAndUnknownCommandsAreRefused) {
  Rig r;
  r.node.command(1, "{not json", 1'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  r.send(1, {{"type", "self_destruct"}}, 2'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  r.send(1, {{"type", "mode"}, {"mode", "TURBO"}}, 3'000);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  EXPECT_EQ(r.node.counter_value("rejected.command.malformed"), 3);
  EXPECT_TRUE(r.bus.on<controller_mode_t>(channels::kMode).empty());
}

// The thruster test's relay: a press needs the token and confirm, stays within the cockpit's
// cap, gets a new test id, is repeated while held and ends at once on let-go, socket close,
// silence or a bad value; one page at a time.
TEST(CockpitNode, ThrusterTestIsRelayedToTheMixerAndEndsOnEveryLoss) {
  Rig r;
  auto tests = [&] { return r.bus.on<thruster_test_t>(channels::kThrusterTest); };
  auto press = [&](int client, std::int64_t n, bool active, double cmd, TimeUs now,
                   bool confirm = true, int thruster = 2) {
    r.send(client,
           {{"type", "thruster_test"},
            {"press", n},
            {"active", active},
            {"thruster", thruster},
            {"command", cmd},
            {"confirm", confirm}},
           now);
  };
  press(1, 1, true, 0.1, 1'000, false);
  EXPECT_EQ(r.last_reply()["error"], "a thruster test needs \"confirm\": true");
  press(1, 1, true, 0.11, 2'000);  // the cockpit's default cap is 0.1
  EXPECT_EQ(r.last_reply()["error"], "command beyond the cockpit's thruster_test.max_command");
  EXPECT_TRUE(tests().empty());
  press(1, 1, true, -0.1, 3'000);
  ASSERT_EQ(tests().size(), 1u);
  const thruster_test_t first = tests().back();
  EXPECT_TRUE(first.active);
  EXPECT_EQ(first.thruster, 2);
  EXPECT_DOUBLE_EQ(first.command, -0.1);
  EXPECT_GE(first.test_id, 1);
  EXPECT_EQ(first.source, "cockpit");
  EXPECT_TRUE(r.last_reply()["ok"].get<bool>());
  // Held: the same id; another page is refused meanwhile.
  press(1, 1, true, -0.1, 103'000);
  EXPECT_EQ(tests().back().test_id, first.test_id);
  press(2, 1, true, 0.1, 104'000);
  EXPECT_EQ(r.last_reply()["error"], "another page is running a thruster test");
  EXPECT_EQ(tests().size(), 2u);
  // Let go: active false at once.
  press(1, 1, false, 0.0, 150'000);
  EXPECT_FALSE(tests().back().active);
  EXPECT_EQ(tests().back().utime, 150'000);
  // A new press: a new id; the socket closes: ended at once.
  press(1, 2, true, 0.05, 200'000);
  EXPECT_GT(tests().back().test_id, first.test_id);
  r.node.client_closed(1, 210'000);
  EXPECT_FALSE(tests().back().active);
  EXPECT_EQ(tests().back().utime, 210'000);
  // Silent for more than timeout_s (0.5 s): ended at the next tick; that press stays ended.
  press(2, 7, true, 0.05, 300'000);
  EXPECT_TRUE(tests().back().active);
  r.node.tick(750'000);
  EXPECT_TRUE(tests().back().active);
  r.node.tick(850'000);
  EXPECT_FALSE(tests().back().active);
  EXPECT_EQ(tests().back().utime, 850'000);
  std::size_t n = tests().size();
  press(2, 7, true, 0.05, 900'000);
  EXPECT_EQ(tests().size(), n);
  EXPECT_EQ(r.last_reply()["error"],
            "this press ended (silent, or a bad value): let go and press again");
  // A bad value while held ends the test too.
  press(2, 8, true, 0.05, 1'000'000);
  n = tests().size();
  EXPECT_TRUE(tests().back().active);
  press(2, 8, true, 0.5, 1'050'000);
  ASSERT_EQ(tests().size(), n + 1);
  EXPECT_FALSE(tests().back().active);
  EXPECT_FALSE(r.last_reply()["ok"].get<bool>());
  // Without the token nothing is sent.
  r.send(3,
         {{"type", "thruster_test"},
          {"press", 1},
          {"active", true},
          {"thruster", 0},
          {"command", 0.1},
          {"confirm", true}},
         1'100'000, false);
  EXPECT_EQ(tests().size(), n + 1);
}

}  // namespace
}  // namespace tiller::cockpit
