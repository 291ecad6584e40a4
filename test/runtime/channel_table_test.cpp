// The channel table (docs/reference/channels.md, section "## Channels") against the nodes
// themselves: each program's node is built from its default config, and what it declares
// (subscribe<Msg>() and advertise<Msg>()) must be exactly what the table says, type included.
// Table rule (stated on that page): a cell of the
// "published by" or "listened to by" columns names programs as `tiller-<name>` in backticks;
// other words there (logs, plots, spy, `--replay`) are free text. Every channel a node declares has
// a row.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cockpit/cockpit_config.hpp"
#include "cockpit/cockpit_node.hpp"
#include "control/control_config.hpp"
#include "control/rov_node.hpp"
#include "control/station_keep_node.hpp"
#include "control/velocity_pid_node.hpp"
#include "core/config.hpp"
#include "esc/esc_node.hpp"
#include "failsafe/failsafe_config.hpp"
#include "failsafe/failsafe_node.hpp"
#include "guidance/follower_config.hpp"
#include "guidance/path_follower_node.hpp"
#include "i2c/fake_bus.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mavlink/mavlink_node.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mixer/mixer_node.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sensors/dvl_node.hpp"
#include "sensors/gnss_node.hpp"
#include "sensors/gpio.hpp"
#include "sensors/imu_node.hpp"
#include "sensors/leak_node.hpp"
#include "sensors/navigator_node.hpp"
#include "sensors/power_node.hpp"
#include "sensors/pressure_node.hpp"
#include "sim/sim_node.hpp"
#include "spi/fake_spi.hpp"
#include "teleop/stick_script.hpp"
#include "teleop/teleop_node.hpp"
#include "teleop/teleop_params.hpp"

namespace tiller {
namespace {

const std::string kRoot = TILLER_SOURCE_DIR;
const std::string kTablePage = "docs/reference/channels.md";  // relative to kRoot

struct Row {
  std::vector<std::string> channels;
  std::string type;
  std::set<std::string> publishers, listeners;  // `tiller-...` names
  int line = 0;
};

std::vector<std::string> backticked(const std::string& cell) {
  std::vector<std::string> out;
  static const std::regex re("`([^`]+)`");
  for (auto it = std::sregex_iterator(cell.begin(), cell.end(), re); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[1]);
  return out;
}

std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cur;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '|') {
      cells.push_back(cur);
      cur.clear();
    } else {
      cur += line[i];
    }
  }
  return cells;
}

std::vector<Row> read_table() {
  std::ifstream in(kRoot + "/" + kTablePage);
  EXPECT_TRUE(in) << "cannot open " << kTablePage;
  std::vector<Row> rows;
  std::string line;
  bool in_section = false;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.rfind("## ", 0) == 0) in_section = line == "## Channels";
    if (!in_section || line.rfind("| `", 0) != 0) continue;
    const auto cells = split_cells(line);
    EXPECT_EQ(cells.size(), 4u) << kTablePage << ":" << n << ": expected 4 cells";
    if (cells.size() != 4) continue;
    Row r;
    r.line = n;
    r.channels = backticked(cells[0]);
    const auto types = backticked(cells[1]);
    EXPECT_EQ(types.size(), 1u) << kTablePage << ":" << n << ": one type per row";
    if (!types.empty()) r.type = types[0];
    auto program = [](const std::string& w) {
      return w.rfind("tiller-", 0) == 0 || w.rfind("lcm-", 0) == 0;
    };
    for (const auto& p : backticked(cells[2]))
      if (program(p)) r.publishers.insert(p);
    for (const auto& p : backticked(cells[3]))
      if (program(p)) r.listeners.insert(p);
    rows.push_back(r);
  }
  return rows;
}

struct Program {
  std::string name;                          // tiller-<name>
  std::vector<std::unique_ptr<Node>> nodes;  // every mode of the program
};

std::vector<Program> programs() {
  std::vector<Program> out;
  auto add = [&](const std::string& name, std::unique_ptr<Node> n) {
    for (auto& p : out) {
      if (p.name == name) {
        p.nodes.push_back(std::move(n));
        return;
      }
    }
    Program p;
    p.name = name;
    p.nodes.push_back(std::move(n));
    out.push_back(std::move(p));
  };
  const auto control = config::Value::load_file(kRoot + "/config/control/otter.yaml");
  add("tiller-velocity-pid",
      std::make_unique<control::VelocityPidNode>(control::load_velocity_pid_node_params(control)));
  add("tiller-station-keep",
      std::make_unique<control::StationKeepNode>(control::load_station_keep_node_params(control)));
  add("tiller-rov-control",
      std::make_unique<control::RovControlNode>(
          control::load_rov_control_file(kRoot + "/config/control/seed001_rov6.yaml")));
  const auto guidance = config::Value::load_file(kRoot + "/config/guidance/default.yaml");
  add("tiller-path-follower",
      std::make_unique<guidance::PathFollowerNode>(guidance::load_follower_node_params(guidance)));
  add("tiller-mixer", std::make_unique<MixerNode>(kRoot + "/config/mixer/otter.yaml"));
  add("tiller-esc", std::make_unique<EscNode>(kRoot + "/config/esc/seed000_sim.yaml"));
  add("tiller-sim", std::make_unique<SimNode>(kRoot + "/config/sim/sim.yaml"));
  const auto teleop = load_teleop_file(kRoot + "/config/teleop/extreme3dpro_seed000.yaml");
  add("tiller-teleop", std::make_unique<TeleopNode>(teleop, TeleopNode::Input::device));
  add("tiller-teleop", std::make_unique<TeleopNode>(teleop, TeleopNode::Input::replay));
  add("tiller-stick-script", std::make_unique<StickScriptNode>(
                                 load_stick_script_file(kRoot + "/config/pilot/rov_demo.yaml")));
  const auto m = mission::load_mission_file(kRoot + "/config/missions/default.yaml");
  add("tiller-mission", std::make_unique<mission::MissionNode>(m, 1, kUsPerSecond));
  mission::StartGateParams gate;  // --start-std-m: it listens to the odometry too
  gate.enabled = true;
  add("tiller-mission", std::make_unique<mission::MissionNode>(m, 1, kUsPerSecond, true, gate));
  // A mission with items (docs/missions.md): it listens to the progress and sends the speeds.
  add("tiller-mission",
      std::make_unique<mission::MissionNode>(
          mission::load_mission_file(kRoot + "/config/missions/harbour.plan"), 1, kUsPerSecond));
  add("tiller-cockpit",
      std::make_unique<cockpit::CockpitNode>(
          cockpit::load_cockpit_file(kRoot + "/config/cockpit/usv_sim.yaml").node,
          "0123456789abcdef",
          [](const std::string&, const std::string&, const std::optional<mission::GeoPoint>&) {
            return mission::Mission{};
          }));
  add("tiller-mavlink",
      std::make_unique<mavlink::MavlinkNode>(
          mavlink::load_mavlink_file(kRoot + "/config/mavlink/usv_sim.yaml").node));
  static i2c::FakeBus i2c;  // the sensor drivers' nodes on an empty fake bus
  add("tiller-pressure",
      std::make_unique<sensors::PressureNode>(
          sensors::load_pressure_file(kRoot + "/config/sensors/pressure_bar30.yaml"), i2c));
  add("tiller-gnss", std::make_unique<sensors::GnssNode>(
                         sensors::load_gnss_file(kRoot + "/config/sensors/gnss_gpsd.yaml")));
  add("tiller-dvl", std::make_unique<sensors::DvlNode>(
                        sensors::load_dvl_file(kRoot + "/config/sensors/dvl_a50.yaml")));
  add("tiller-imu", std::make_unique<sensors::ImuNode>(
                        sensors::load_imu_file(kRoot + "/config/sensors/imu_bno055.yaml"), i2c));
  static spi::FakeSpi spi;
  add("tiller-navigator",
      std::make_unique<sensors::NavigatorNode>(
          sensors::load_navigator_file(kRoot + "/config/sensors/navigator.yaml"), spi, i2c));
  add("tiller-power",
      std::make_unique<sensors::PowerNode>(
          sensors::load_power_file(kRoot + "/config/sensors/power_ina226.yaml"), i2c));
  add("tiller-failsafe", std::make_unique<failsafe::FailsafeNode>(failsafe::load_failsafe_file(
                             kRoot + "/config/failsafe/seed001_rov6.yaml")));
  static sensors::FakeGpio gpio;
  add("tiller-leak", std::make_unique<sensors::LeakNode>(
                         sensors::load_leak_file(kRoot + "/config/sensors/leak_gpio.yaml"), gpio));
  add("tiller-nav",
      std::make_unique<nav::NavNode>(nav::load_nav_file(kRoot + "/config/nav/usv.yaml")));
  return out;
}

// Programs that are not nodes but may be named in the table.
const std::set<std::string> kTools = {"tiller-log",    "tiller-score",  "tiller-plot",
                                      "tiller-replay", "tiller-launch", "lcm-logger",
                                      "lcm-spy"};

TEST(ChannelTable, DocsTableMatchesWhatEveryNodeDeclares) {
  const auto rows = read_table();
  ASSERT_GT(rows.size(), 15u) << "no channel table found under '## Channels' in " << kTablePage;
  const auto progs = programs();
  std::set<std::string> names;
  for (const auto& p : progs) names.insert(p.name);

  // Every name in the table is a program the test knows.
  for (const auto& r : rows) {
    for (const auto* set : {&r.publishers, &r.listeners}) {
      for (const auto& n : *set) {
        EXPECT_TRUE(names.count(n) || kTools.count(n))
            << kTablePage << ":" << r.line << ": unknown program `" << n << "`";
      }
    }
  }

  std::map<std::string, const Row*> by_channel;
  for (const auto& r : rows)
    for (const auto& c : r.channels) by_channel[c] = &r;

  for (const auto& p : progs) {
    std::set<std::string> pubs, subs;
    for (const auto& n : p.nodes) {
      for (const auto& c : n->published_channels()) {
        if (c == n->heartbeat_channel()) continue;  // the TILLER_HEARTBEAT_<PROCESS> row
        pubs.insert(c);
        const auto it = by_channel.find(c);
        if (it == by_channel.end()) continue;
        EXPECT_EQ(it->second->type, n->published_type(c)) << kTablePage << ":" << it->second->line;
      }
      for (const auto& sc : n->subscribed_channels()) {
        // Other processes' heartbeats (tiller-cockpit shows them) are the one
        // TILLER_HEARTBEAT_<PROCESS> row.
        const std::string c = sc.rfind(channels::kHeartbeatPrefix, 0) == 0
                                  ? std::string(channels::kHeartbeatPrefix) + "<PROCESS>"
                                  : sc;
        subs.insert(c);
        const auto it = by_channel.find(c);
        if (it == by_channel.end()) continue;
        EXPECT_EQ(it->second->type, n->subscribed_type(sc))
            << kTablePage << ":" << it->second->line;
      }
      EXPECT_EQ(n->heartbeat_channel().rfind(channels::kHeartbeatPrefix, 0), 0u);
    }
    for (const auto& c : pubs) {
      const auto it = by_channel.find(c);
      ASSERT_NE(it, by_channel.end())
          << p.name << " publishes " << c << ": no row in " << kTablePage;
      EXPECT_TRUE(it->second->publishers.count(p.name))
          << kTablePage << ":" << it->second->line << ": " << c << ": `" << p.name
          << "` publishes it but is not in 'published by'";
    }
    for (const auto& c : subs) {
      const auto it = by_channel.find(c);
      ASSERT_NE(it, by_channel.end())
          << p.name << " listens to " << c << ": no row in " << kTablePage;
      EXPECT_TRUE(it->second->listeners.count(p.name))
          << kTablePage << ":" << it->second->line << ": " << c << ": `" << p.name
          << "` listens to it but is not in 'listened to by'";
    }
    for (const auto& r : rows) {
      for (const auto& c : r.channels) {
        if (r.publishers.count(p.name)) {
          EXPECT_TRUE(pubs.count(c)) << kTablePage << ":" << r.line << ": " << c << ": `" << p.name
                                     << "` is listed as a publisher but does not advertise it";
        }
        if (r.listeners.count(p.name)) {
          EXPECT_TRUE(subs.count(c)) << kTablePage << ":" << r.line << ": " << c << ": `" << p.name
                                     << "` is listed as a listener but does not subscribe";
        }
      }
    }
  }
  EXPECT_TRUE(by_channel.count(std::string(channels::kHeartbeatPrefix) + "<PROCESS>"));
}

// Publishing on a channel that was never advertised is counted (and still published).
class Sloppy : public Node {
 public:
  Sloppy() : Node("sloppy", 1000) { advertise<heartbeat_t>("DECLARED"); }
  void on_tick(TimeUs now) override {
    heartbeat_t h{};
    h.utime = now;
    publish("DECLARED", h);
    publish("UNDECLARED", h);
  }
};

TEST(ChannelTable, UnadvertisedPublishIsCounted) {
  Sloppy s;
  s.tick(0);
  s.tick(1000);
  EXPECT_EQ(s.counter_value("unadvertised.UNDECLARED"), 2);
  EXPECT_EQ(s.counter_value("unadvertised.DECLARED"), 0);
  EXPECT_EQ(s.published_channels(),
            (std::vector<std::string>{"DECLARED", "TILLER_HEARTBEAT_SLOPPY"}));
  EXPECT_EQ(s.published_type("DECLARED"), "heartbeat_t");
}

// The whole stack in lockstep for a minute of a mission: no node publishes on a channel it did
// not advertise (no "unadvertised.*" counter in any heartbeat), and every channel that goes on
// the bus has a row in the channel table.
TEST(ChannelTable, FullStackPublishesOnlyWhatItAdvertises) {
  const auto control = config::Value::load_file(kRoot + "/config/control/seed004_usv_x.yaml");
  control::VelocityPidNode pid(control::load_velocity_pid_node_params(control));
  control::StationKeepNode station(control::load_station_keep_node_params(control));
  const auto guidance = config::Value::load_file(kRoot + "/config/guidance/default.yaml");
  guidance::PathFollowerNode follower(guidance::load_follower_node_params(guidance));
  MixerNode mixer(kRoot + "/config/mixer/seed004_usv_x.yaml");
  EscNode esc(kRoot + "/config/esc/seed004_usv_x_sim.yaml");
  SimNode sim(kRoot + "/config/sim/sim.yaml");
  mission::MissionNode mission(mission::load_mission_file(kRoot + "/config/missions/default.yaml"),
                               1, kUsPerSecond);
  LockstepExecutor ex(0);
  for (Node* n :
       std::initializer_list<Node*>{&sim, &esc, &mixer, &pid, &station, &follower, &mission})
    ex.add(*n);
  std::set<std::string> on_bus, unadvertised;
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs) {
    on_bus.insert(ch);
    heartbeat_t h;
    if (ch.rfind(channels::kHeartbeatPrefix, 0) != 0 || h.decode(d, 0, n) != n) return;
    for (int i = 0; i < h.n_counters; ++i) {
      if (h.counter_names[i].rfind("unadvertised.", 0) == 0)
        unadvertised.insert(h.process + ": " + h.counter_names[i]);
    }
  });
  ex.run_until(60 * kUsPerSecond);
  EXPECT_TRUE(unadvertised.empty()) << *unadvertised.begin();
  EXPECT_GT(on_bus.size(), 15u);
  std::printf("%zu channels on the bus, %lld thruster commands at the ESC\n", on_bus.size(),
              static_cast<long long>(esc.received()));
  const auto rows = read_table();
  std::set<std::string> in_table;
  for (const auto& r : rows) in_table.insert(r.channels.begin(), r.channels.end());
  for (const auto& ch : on_bus) {
    if (ch.rfind(channels::kHeartbeatPrefix, 0) == 0) continue;
    EXPECT_TRUE(in_table.count(ch)) << ch << " is on the bus but has no row in " << kTablePage;
  }
}

}  // namespace
}  // namespace tiller
