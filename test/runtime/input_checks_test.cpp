// Checks everywhere: every (node, channel) pair, taken from the nodes' own declarations
// (subscribed_channels() and subscribed_type()), refuses every bad value of its type
// (test/common/bad_values.hpp: out of range and non-finite) with a counted drop, and its outputs
// stay byte-identical to the run without the bad message.
//
// Every node class in lib/ (found by reading the headers for "class X : public Node") must be
// built here, from every shipped config of its program (config/<program dir>/*.yaml; the
// simulator once per vehicle file), so a new node, config or subscription is covered without
// editing this test, or the test fails saying what is not covered.
//
// One run: good input (bad_values.hpp good<>()) on every subscribed channel every 50 ms for
// 1.5 s in lockstep, every published message recorded except the heartbeat (whose counters
// show the drop). The same run plus one bad message at 0.525 s must give rejected() one more
// and the same bytes on every output channel; for the mixer, which answers a refused input from
// the source in control with neutral at once (the last stage before the ESCs), every output
// that differs must be neutral.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "bad_values.hpp"
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
#include "launch/launch_file.hpp"
#include "launch/monitor.hpp"
#include "mavlink/mavlink_config.hpp"
#include "mavlink/mavlink_node.hpp"
#include "mission/mission.hpp"
#include "mission/mission_node.hpp"
#include "mixer/mixer_node.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/channels.hpp"
#include "runtime/lockstep.hpp"
#include "sensors/ads1115_power_node.hpp"
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

namespace fs = std::filesystem;
using test::InputContext;
using test::TypeInputs;

const std::string kRoot = TILLER_SOURCE_DIR;
constexpr TimeUs kPeriod = 50'000;
constexpr TimeUs kBadAt = 525'000;
constexpr TimeUs kEnd = 1'500'000;

// An output message (channel, encoded bytes) that is safe whatever the input was.
using SafeOutput =
    std::function<bool(const std::string& channel, const std::vector<std::uint8_t>&)>;

struct NodeCase {
  std::string cls;    // C++ class name
  std::string label;  // program and config, for messages
  std::function<std::unique_ptr<Node>(InputContext&)> make;
  // Set for a node that answers a refused input by going neutral at once instead of keeping
  // the last good one (the mixer: a bad message from the source in control makes that source
  // absent). Its outputs may then differ from the reference run only by being neutral.
  SafeOutput neutral = nullptr;
};

// The mixer's neutral: every thruster command 0, and the allocation of nothing.
bool mixer_neutral(const std::string& ch, const std::vector<std::uint8_t>& bytes) {
  const int n = static_cast<int>(bytes.size());
  if (ch == channels::kThrusterCommand) {
    thruster_command_t m;
    if (m.decode(bytes.data(), 0, n) != n) return false;
    return std::all_of(m.command.begin(), m.command.end(), [](double c) { return c == 0.0; });
  }
  if (ch == channels::kAllocationStatus) {
    allocation_status_t m;
    if (m.decode(bytes.data(), 0, n) != n) return false;
    return std::all_of(std::begin(m.achieved), std::end(m.achieved),
                       [](double a) { return a == 0.0; });
  }
  return false;
}

std::vector<std::string> shipped(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(kRoot + "/config/" + dir))
    if (e.path().extension() == ".yaml") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::string rel(const std::string& p) {
  return fs::relative(p, kRoot).string();
}

// One fake I2C bus for every hardware ESC config (no /dev/i2c-* here); it outlives the nodes.
i2c::FakeBus& fake_bus() {
  static i2c::FakeBus bus;
  return bus;
}

// A LaunchMonitor with its own supervisor (never started: no process is spawned).
struct NoHost : launch::ProcessHost {
  int spawn(const launch::ProcessSpec&, std::string&) override { return -1; }
  void signal(int, int) override {}
};
struct SupervisorBox {
  explicit SupervisorBox(std::vector<launch::ProcessSpec> p) : sup(std::move(p), "", 1.0, host) {}
  NoHost host;
  launch::Supervisor sup;
};
struct OwnedMonitor : SupervisorBox, launch::LaunchMonitor {
  explicit OwnedMonitor(std::vector<launch::ProcessSpec> p)
      : SupervisorBox(std::move(p)), LaunchMonitor(sup) {}
};

std::vector<NodeCase> node_cases() {
  std::vector<NodeCase> out;
  for (const auto& f : shipped("control")) {
    if (config::Value::load_file(f).has("rov_control")) {  // an ROV's: tiller-rov-control
      out.push_back({"RovControlNode", "tiller-rov-control " + rel(f), [f](InputContext& ctx) {
                       ctx.thrusters = {"t1", "t2"};  // its gate input: names not checked
                       return std::make_unique<control::RovControlNode>(
                           control::load_rov_control_file(f));
                     }});
      continue;
    }
    // The controllers read the mixer's thruster commands (its gate): a two-thruster command.
    out.push_back({"VelocityPidNode", "tiller-velocity-pid " + rel(f), [f](InputContext& ctx) {
                     ctx.thrusters = {"port", "starboard"};
                     return std::make_unique<control::VelocityPidNode>(
                         control::load_velocity_pid_node_params(config::Value::load_file(f)));
                   }});
    out.push_back({"StationKeepNode", "tiller-station-keep " + rel(f), [f](InputContext& ctx) {
                     ctx.thrusters = {"port", "starboard"};
                     return std::make_unique<control::StationKeepNode>(
                         control::load_station_keep_node_params(config::Value::load_file(f)));
                   }});
  }
  for (const auto& f : shipped("guidance")) {
    out.push_back({"PathFollowerNode", "tiller-path-follower " + rel(f), [f](InputContext&) {
                     return std::make_unique<guidance::PathFollowerNode>(
                         guidance::load_follower_node_params(config::Value::load_file(f)));
                   }});
  }
  for (const auto& f : shipped("mixer")) {
    out.push_back({"MixerNode", "tiller-mixer " + rel(f),
                   [f](InputContext&) { return std::make_unique<MixerNode>(f); }, mixer_neutral});
  }
  for (const auto& f : shipped("esc")) {
    out.push_back({"EscNode", "tiller-esc " + rel(f), [f](InputContext& ctx) {
                     auto n = std::make_unique<EscNode>(f, fake_bus());
                     for (std::size_t i = 0; i < n->backend().size(); ++i)
                       ctx.thrusters.push_back(n->backend().channel(i).name);
                     return n;
                   }});
  }
  for (const auto& s : shipped("sim")) {
    for (const auto& v : shipped("vehicles")) {
      out.push_back(
          {"SimNode", "tiller-sim " + rel(s) + " --vehicle " + rel(v), [s, v](InputContext& ctx) {
             const auto root = config::Value::load_file(s);
             root.mark_used();
             auto n = std::make_unique<SimNode>(load_sim_params(root), load_sim_vehicle_file(v));
             for (const auto& t : n->vehicle().thrusters) ctx.thrusters.push_back(t.name);
             return n;
           }});
    }
  }
  for (const auto& f : shipped("teleop")) {
    for (auto in : {TeleopNode::Input::device, TeleopNode::Input::replay}) {
      const std::string mode = in == TeleopNode::Input::replay ? " --replay" : "";
      out.push_back({"TeleopNode", "tiller-teleop " + rel(f) + mode, [f, in](InputContext&) {
                       return std::make_unique<TeleopNode>(load_teleop_file(f), in);
                     }});
    }
  }
  for (const auto& f : shipped("pilot")) {
    out.push_back({"StickScriptNode", "tiller-stick-script " + rel(f), [f](InputContext&) {
                     return std::make_unique<StickScriptNode>(load_stick_script_file(f));
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("pressure", 0) != 0) continue;
    out.push_back({"PressureNode", "tiller-pressure " + rel(f), [f](InputContext&) {
                     return std::make_unique<sensors::PressureNode>(sensors::load_pressure_file(f),
                                                                    fake_bus());
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("gnss", 0) != 0) continue;
    out.push_back({"GnssNode", "tiller-gnss " + rel(f), [f](InputContext&) {
                     return std::make_unique<sensors::GnssNode>(sensors::load_gnss_file(f));
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("dvl", 0) != 0) continue;
    out.push_back({"DvlNode", "tiller-dvl " + rel(f), [f](InputContext&) {
                     return std::make_unique<sensors::DvlNode>(sensors::load_dvl_file(f));
                   }});
  }
  for (const auto& f : shipped("cockpit")) {
    out.push_back(
        {"CockpitNode", "tiller-cockpit " + rel(f), [f](InputContext& ctx) {
           ctx.thrusters = {"port", "starboard"};  // it shows any vehicle's
           return std::make_unique<cockpit::CockpitNode>(
               cockpit::load_cockpit_file(f).node, "0123456789abcdef",
               [](const std::string&, const std::string&, const std::optional<mission::GeoPoint>&) {
                 return mission::Mission{};
               });
         }});
  }
  for (const auto& f : shipped("mavlink")) {
    out.push_back({"MavlinkNode", "tiller-mavlink " + rel(f), [f](InputContext& ctx) {
                     ctx.thrusters = {"port", "starboard"};  // it reports any vehicle's
                     return std::make_unique<mavlink::MavlinkNode>(
                         mavlink::load_mavlink_file(f).node);
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("imu", 0) != 0) continue;
    out.push_back({"ImuNode", "tiller-imu " + rel(f), [f](InputContext&) {
                     return std::make_unique<sensors::ImuNode>(sensors::load_imu_file(f),
                                                               fake_bus());
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("navigator", 0) != 0) continue;
    out.push_back({"NavigatorNode", "tiller-navigator " + rel(f), [f](InputContext&) {
                     static spi::FakeSpi spi;
                     return std::make_unique<sensors::NavigatorNode>(
                         sensors::load_navigator_file(f), spi, fake_bus());
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("power", 0) != 0) continue;
    const auto root = config::Value::load_file(f);
    if (root.string_or("device", "ina226") == "ads1115") {
      out.push_back({"Ads1115PowerNode", "tiller-power " + rel(f), [f](InputContext&) {
                       return std::make_unique<sensors::Ads1115PowerNode>(
                           sensors::load_ads1115_power_params(config::Value::load_file(f)),
                           fake_bus());
                     }});
      continue;
    }
    out.push_back({"PowerNode", "tiller-power " + rel(f), [f](InputContext&) {
                     return std::make_unique<sensors::PowerNode>(sensors::load_power_file(f),
                                                                 fake_bus());
                   }});
  }
  for (const auto& f : shipped("sensors")) {
    if (fs::path(f).filename().string().rfind("leak", 0) != 0) continue;
    out.push_back({"LeakNode", "tiller-leak " + rel(f), [f](InputContext&) {
                     static sensors::FakeGpio gpio;  // outlives the nodes
                     return std::make_unique<sensors::LeakNode>(sensors::load_leak_file(f), gpio);
                   }});
  }
  for (const auto& f : shipped("nav")) {
    out.push_back({"NavNode", "tiller-nav " + rel(f), [f](InputContext&) {
                     return std::make_unique<nav::NavNode>(nav::load_nav_file(f));
                   }});
  }
  // tiller-launch's monitor, watching every process of each shipped launch file.
  for (const auto& f : shipped("launch")) {
    out.push_back({"LaunchMonitor", "tiller-launch " + rel(f), [f](InputContext&) {
                     return std::make_unique<OwnedMonitor>(launch::load_launch_file(f).processes);
                   }});
  }
  for (const auto& f : shipped("failsafe")) {
    out.push_back({"FailsafeNode", "tiller-failsafe " + rel(f), [f](InputContext&) {
                     return std::make_unique<failsafe::FailsafeNode>(
                         failsafe::load_failsafe_file(f));
                   }});
  }
  for (const auto& f : shipped("missions")) {
    out.push_back({"MissionNode", "tiller-mission " + rel(f), [f](InputContext&) {
                     return std::make_unique<mission::MissionNode>(mission::load_mission_file(f), 1,
                                                                   kUsPerSecond);
                   }});
    out.push_back({"MissionNode", "tiller-mission --start-std-m 0.3 " + rel(f), [f](InputContext&) {
                     mission::StartGateParams gate;  // the start gate: it takes the odometry too
                     gate.enabled = true;
                     gate.max_position_std_m = 0.3;
                     return std::make_unique<mission::MissionNode>(mission::load_mission_file(f), 1,
                                                                   kUsPerSecond, true, gate);
                   }});
  }
  return out;
}

// Every "class X : public Node" in lib/.
std::map<std::string, std::string> node_classes_in_lib() {
  static const std::regex re(R"(class\s+(\w+)\s*(?:final\s*)?:\s*public\s+(?:tiller::)?Node\b)");
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(kRoot + "/lib")) {
    if (e.path().extension() != ".hpp") continue;
    std::ifstream in(e.path());
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
         ++it)
      out[(*it)[1]] = rel(e.path().string());
  }
  return out;
}

struct Output {
  std::string channel;
  TimeUs time;
  std::vector<std::uint8_t> bytes;
  bool operator==(const Output&) const = default;
};
using Outputs = std::vector<Output>;

struct RunResult {
  Outputs outputs;
  std::int64_t rejected = 0;
  std::int64_t received = 0;
};

const TypeInputs* inputs_for(const std::vector<TypeInputs>& all, const std::string& type) {
  for (const auto& t : all)
    if (t.type == type) return &t;
  return nullptr;
}

// Good input on every subscribed channel; `extra` (if any) injected at kBadAt.
RunResult run(const NodeCase& nc, const std::vector<TypeInputs>& all, const Event* extra) {
  InputContext ctx;
  auto node = nc.make(ctx);
  LockstepExecutor ex(0);
  ex.add(*node);
  RunResult r;
  std::set<std::string> outs;
  // A channel the node both publishes and listens to (tiller-cockpit shows TILLER_MODE and
  // TILLER_PATH, and sends them only on a page's command) would count the injected inputs as
  // outputs: only channels it does not also listen to are compared.
  for (const auto& c : node->published_channels())
    if (c != node->heartbeat_channel() && !node->subscribes_to(c)) outs.insert(c);
  ex.observe([&](const std::string& ch, const std::uint8_t* d, int n, TimeUs t) {
    if (outs.count(ch)) r.outputs.push_back({ch, t, std::vector<std::uint8_t>(d, d + n)});
  });
  for (TimeUs t = 0; t < kEnd; t += kPeriod) {
    for (const auto& ch : node->subscribed_channels()) {
      const TypeInputs* ti = inputs_for(all, node->subscribed_type(ch));
      if (ti) ex.inject(ti->good(ch, t, ctx));
    }
  }
  if (extra) ex.inject(*extra);
  ex.run_until(kEnd);
  r.rejected = node->rejected();
  r.received = node->received();
  return r;
}

TEST(InputChecks, EveryNodeClassInLibIsBuiltFromItsShippedConfigs) {
  std::set<std::string> built;
  for (const auto& nc : node_cases()) built.insert(nc.cls);
  const auto classes = node_classes_in_lib();
  ASSERT_GE(classes.size(), 8u);
  for (const auto& [cls, where] : classes) {
    EXPECT_TRUE(built.count(cls)) << cls << " (" << where
                                  << ") is a Node that input_checks_test does not build: add it "
                                     "to node_cases() with its shipped configs";
  }
}

TEST(InputChecks, EverySubscribedTypeHasBadValuesOfBothKinds) {
  const auto all = test::all_type_inputs();
  for (const auto& nc : node_cases()) {
    InputContext ctx;
    auto node = nc.make(ctx);
    for (const auto& ch : node->subscribed_channels()) {
      const std::string type = node->subscribed_type(ch);
      const TypeInputs* ti = inputs_for(all, type);
      ASSERT_NE(ti, nullptr) << nc.label << " subscribes to " << ch << " (" << type
                             << "): no inputs for this type in test/common/bad_values.hpp";
      for (auto kind : {test::BadKind::kNonFinite, test::BadKind::kRange}) {
        const bool have = std::any_of(ti->bad.begin(), ti->bad.end(),
                                      [kind](const TypeInputs::Bad& b) { return b.kind == kind; });
        const bool declared_missing =
            std::any_of(ti->missing.begin(), ti->missing.end(),
                        [kind](const test::MissingKind& m) { return m.kind == kind; });
        EXPECT_TRUE(have || declared_missing)
            << type << " has no " << test::kind_name(kind) << " bad value (bad_values.hpp)";
        if (declared_missing) {
          EXPECT_EQ(ti->missing_hash, ti->hash)
              << type << " changed since bad_values.hpp said it has no " << test::kind_name(kind)
              << " value: give it bad values (or update missing_kinds_hash to 0x" << std::hex
              << ti->hash << ")";
        }
      }
    }
  }
}

TEST(InputChecks, EveryBadValueOnEverySubscriptionIsDroppedCountedAndChangesNothing) {
  const auto all = test::all_type_inputs();
  int pairs = 0, cases = 0;
  for (const auto& nc : node_cases()) {
    SCOPED_TRACE(nc.label);
    const RunResult ref = run(nc, all, nullptr);
    InputContext ctx;
    auto probe = nc.make(ctx);
    const auto subs = probe->subscribed_channels();
    if (subs.empty()) continue;
    ASSERT_EQ(ref.rejected, 0) << nc.label << ": the good input itself is refused";
    ASSERT_GT(ref.received, 0);
    for (const auto& ch : subs) {
      const TypeInputs* ti = inputs_for(all, probe->subscribed_type(ch));
      if (ti == nullptr) continue;  // reported by EverySubscribedTypeHasBadValuesOfBothKinds
      ++pairs;
      for (const auto& b : ti->bad) {
        ++cases;
        const Event e = b.make(ch, kBadAt, ctx);
        const RunResult got = run(nc, all, &e);
        EXPECT_EQ(got.rejected, 1) << nc.label << ": " << ch << " " << b.what << " ("
                                   << test::kind_name(b.kind) << ") was not refused";
        if (nc.neutral) {
          // Every output not in the reference run is neutral.
          for (const auto& o : got.outputs) {
            if (std::find(ref.outputs.begin(), ref.outputs.end(), o) != ref.outputs.end()) continue;
            EXPECT_TRUE(nc.neutral(o.channel, o.bytes))
                << nc.label << ": " << ch << " " << b.what << ": an output on " << o.channel
                << " at " << o.time << " us is neither the reference's nor neutral";
          }
          continue;
        }
        EXPECT_EQ(got.outputs.size(), ref.outputs.size())
            << nc.label << ": " << ch << " " << b.what << " changed the number of outputs";
        bool same = got.outputs.size() == ref.outputs.size();
        for (std::size_t i = 0; same && i < ref.outputs.size(); ++i) {
          if (!(got.outputs[i] == ref.outputs[i])) {
            same = false;
            ADD_FAILURE() << nc.label << ": " << ch << " " << b.what << " changed output " << i
                          << " on " << ref.outputs[i].channel;
          }
        }
      }
    }
  }
  EXPECT_GT(pairs, 50);
  EXPECT_GT(cases, 200);
  std::printf("%d (node config, channel) pairs, %d bad messages\n", pairs, cases);
}

}  // namespace
}  // namespace tiller
