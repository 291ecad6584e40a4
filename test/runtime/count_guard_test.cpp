// The generated pre-decode guard (tools/lcm-count-guard.py -> tiller/count_guard.hpp):
// valid traffic of every contract type passes, truncated packets and packets whose array counts
// cannot fit are refused, and such a packet delivered to a node is counted as malformed without
// any heap allocation (lcm-gen 1.3.1 would resize to the count first). operator new is counted
// for this whole binary.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include <tiller/allocation_status_t.hpp>
#include <tiller/arbitration_t.hpp>
#include <tiller/arm_request_t.hpp>
#include <tiller/arm_state_t.hpp>
#include <tiller/controller_mode_t.hpp>
#include <tiller/count_guard.hpp>
#include <tiller/datum_t.hpp>
#include <tiller/dvl_t.hpp>
#include <tiller/esc_bus_status_t.hpp>
#include <tiller/esc_output_t.hpp>
#include <tiller/esc_telemetry_t.hpp>
#include <tiller/gnss_fix_t.hpp>
#include <tiller/heading_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/imu_t.hpp>
#include <tiller/joystick_state_t.hpp>
#include <tiller/leak_t.hpp>
#include <tiller/manual_demand_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>
#include <tiller/mission_command_t.hpp>
#include <tiller/odometry_t.hpp>
#include <tiller/path_progress_t.hpp>
#include <tiller/path_speed_t.hpp>
#include <tiller/path_t.hpp>
#include <tiller/pid_terms_t.hpp>
#include <tiller/power_t.hpp>
#include <tiller/pressure_t.hpp>
#include <tiller/sim_state_t.hpp>
#include <tiller/station_target_t.hpp>
#include <tiller/thruster_command_t.hpp>
#include <tiller/thruster_test_t.hpp>
#include <tiller/vehicle_status_t.hpp>
#include <tiller/velocity_setpoint_t.hpp>
#include <tiller/waypoint_t.hpp>
#include <tiller/wrench_t.hpp>

#include "alloc_count.hpp"
#include "runtime/event.hpp"
#include "runtime/node.hpp"

namespace tiller {
namespace {

template <class M>
std::vector<std::uint8_t> encode(const M& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(b.data(), 0, static_cast<int>(b.size())), static_cast<int>(b.size()));
  return b;
}

// A valid packet passes; every strict prefix of it (a truncated packet) is refused.
template <class M>
void expect_valid_passes_and_prefixes_fail(const M& m, const char* what) {
  const auto b = encode(m);
  EXPECT_TRUE(counts_fit<M>(b.data(), static_cast<int>(b.size())))
      << M::getTypeName() << " (" << what << "), " << b.size() << " bytes";
  for (std::size_t n = 0; n < b.size(); ++n)
    EXPECT_FALSE(counts_fit<M>(b.data(), static_cast<int>(n)))
        << M::getTypeName() << " (" << what << ") truncated to " << n << " of " << b.size();
}

template <class M>
void check(const std::function<void(M&)>& fill) {
  expect_valid_passes_and_prefixes_fail(M{}, "default");
  M m{};
  fill(m);
  expect_valid_passes_and_prefixes_fail(m, "filled");
}

const std::vector<std::string> kNames = {"bow_port", "bow_starboard", "stern"};

// One entry per contract type: fills its variable arrays (a few elements) and strings.
std::map<std::string, std::function<void()>> checks() {
  std::map<std::string, std::function<void()>> c;
  c["allocation_status_t"] = [] {
    check<allocation_status_t>([](auto& m) {
      m.strategy = "prioritised";
      m.n_thrusters = 3;
      m.names = kNames;
      m.saturated = {true, false, true};
    });
  };
  c["arbitration_t"] = [] { check<arbitration_t>([](auto& m) { m.reason = "manual"; }); };
  c["arm_request_t"] = [] { check<arm_request_t>([](auto& m) { m.source = "teleop"; }); };
  c["arm_state_t"] = [] { check<arm_state_t>([](auto& m) { m.reason = "armed by teleop"; }); };
  c["controller_mode_t"] = [] { check<controller_mode_t>([](auto& m) { m.source = "mission"; }); };
  c["esc_bus_status_t"] = [] {
    check<esc_bus_status_t>([](auto& m) {
      m.backend = "i2c_tgy";
      m.bus = "/dev/i2c-1";
      m.n_escs = 3;
      m.names = kNames;
      m.present = {true, true, false};
      m.write_errors = {0, 1, 2};
      m.read_errors = {3, 4, 5};
      m.last_errno = {0, 5, 121};
    });
  };
  c["esc_output_t"] = [] {
    check<esc_output_t>([](auto& m) {
      m.backend = "pca9685";
      m.n_channels = 3;
      m.names = kNames;
      m.channel = {0, 1, 2};
      m.value = {1500, 1600, 1400};
      m.normalized = {0.0, 0.25, -0.25};
    });
  };
  c["esc_telemetry_t"] = [] {
    check<esc_telemetry_t>([](auto& m) {
      m.n_escs = 3;
      m.names = kNames;
      m.address = {0x29, 0x2a, 0x2b};
      m.sample_utime = {1, 2, 3};
      m.rpm = {100, 200, 300};
      m.voltage = {12, 12, 12};
      m.current = {1, 2, 3};
      m.temperature = {30, 31, 32};
      m.alive = {true, true, false};
    });
  };
  c["heartbeat_t"] = [] {
    check<heartbeat_t>([](auto& m) {
      m.process = "mixer";
      m.status = "ok";
      m.n_counters = 2;
      m.counter_names = {"rejected.odometry.nan", "malformed.TILLER_ODOMETRY"};
      m.counter_values = {4, 5};
    });
  };
  c["joystick_state_t"] = [] {
    check<joystick_state_t>([](auto& m) {
      m.device = "/dev/input/js0";
      m.n_axes = 4;
      m.axes = {-32767, 0, 1, 32767};
      m.n_buttons = 2;
      m.buttons = {true, false};
    });
  };
  c["manual_demand_t"] = [] { check<manual_demand_t>([](auto& m) { m.demand[0] = 0.5; }); };
  c["manual_velocity_cmd_t"] = [] {
    check<manual_velocity_cmd_t>([](auto& m) { m.yaw_rate = 0.1; });
  };
  c["odometry_t"] = [] {
    check<odometry_t>([](auto& m) {
      m.n_pose_cov = 36;
      m.pose_covariance.assign(36, 0.01);
      m.n_velocity_cov = 36;
      m.velocity_covariance.assign(36, 0.02);
    });
  };
  c["mission_command_t"] = [] {
    check<mission_command_t>([](auto& m) { m.source = "tiller-mission"; });
  };
  c["path_progress_t"] = [] { check<path_progress_t>([](auto& m) { m.segment = 2; }); };
  c["path_speed_t"] = [] {
    check<path_speed_t>([](auto& m) {
      m.n_segments = 3;
      m.speed = {0, 1.0, 1.5};
    });
  };
  c["datum_t"] = [] {
    check<datum_t>([](auto& m) {
      m.latitude = 59.437;
      m.source = datum_t::SOURCE_FIRST_FIX;
    });
  };
  c["path_t"] = [] {
    check<path_t>([](auto& m) {
      m.n_waypoints = 3;
      m.waypoints.resize(3);
      m.waypoints[1].has_heading = true;
      m.waypoints[2].position[0] = 10.0;
    });
  };
  c["pid_terms_t"] = [] { check<pid_terms_t>([](auto& m) { m.controller = "velocity"; }); };
  c["sim_state_t"] = [] {
    check<sim_state_t>([](auto& m) {
      m.n_thrusters = 3;
      m.names = kNames;
      m.thrust = {1, 2, 3};
    });
  };
  c["station_target_t"] = [] { check<station_target_t>([](auto& m) { m.active = true; }); };
  c["thruster_command_t"] = [] {
    check<thruster_command_t>([](auto& m) {
      m.n_thrusters = 3;
      m.names = kNames;
      m.command = {0.5, -0.5, 1.0};
    });
  };
  c["velocity_setpoint_t"] = [] { check<velocity_setpoint_t>([](auto& m) { m.active = true; }); };
  c["waypoint_t"] = [] { check<waypoint_t>([](auto& m) { m.heading = 1.0; }); };
  c["wrench_t"] = [] { check<wrench_t>([](auto& m) { m.tau[5] = 2.0; }); };
  // Sensors.
  c["gnss_fix_t"] = [] { check<gnss_fix_t>([](auto& m) { m.device = "/dev/ttyACM0"; }); };
  c["imu_t"] = [] { check<imu_t>([](auto& m) { m.orientation[0] = 1.0; }); };
  c["heading_t"] = [] { check<heading_t>([](auto& m) { m.device = "sim"; }); };
  c["pressure_t"] = [] { check<pressure_t>([](auto& m) { m.sensor = "ms5837-30ba"; }); };
  c["power_t"] = [] { check<power_t>([](auto& m) { m.monitor = "ina226"; }); };
  c["leak_t"] = [] {
    check<leak_t>([](auto& m) {
      m.n_probes = 3;
      m.names = kNames;
      m.wet = {false, true, false};
      m.readable = {true, true, true};
      m.any_wet = true;
    });
  };
  c["dvl_t"] = [] { check<dvl_t>([](auto& m) { m.sensor = "dvl-a50"; }); };
  c["vehicle_status_t"] = [] { check<vehicle_status_t>([](auto& m) { m.reason = "leak"; }); };
  c["thruster_test_t"] = [] { check<thruster_test_t>([](auto& m) { m.source = "cockpit"; }); };
  return c;
}

TEST(CountGuard, EveryContractTypeIsGuardedAndValidTrafficPasses) {
  const auto c = checks();
  std::set<std::string> in_dir,
      in_guard(std::begin(count_guard_types), std::end(count_guard_types));
  for (const auto& e : std::filesystem::directory_iterator(TILLER_SOURCE_DIR "/lcmtypes"))
    if (e.path().extension() == ".lcm") in_dir.insert(e.path().stem().string());
  ASSERT_FALSE(in_dir.empty());
  EXPECT_EQ(in_guard, in_dir) << "count_guard.hpp must cover exactly lcmtypes/*.lcm";
  for (const auto& t : in_dir) {
    auto it = c.find(t);
    if (it == c.end()) {
      ADD_FAILURE() << "lcmtypes/" << t << ".lcm has no check in count_guard_test.cpp";
      continue;
    }
    SCOPED_TRACE(t);
    it->second();
  }
  EXPECT_EQ(c.size(), in_dir.size()) << "a check names a type that is not in lcmtypes/";
}

// The encoding of `m` with its first variable count set to `count`: the count's bytes are found
// as the first byte that differs between count 0 and count 1 (its big-endian low byte).
template <class M>
std::vector<std::uint8_t> with_count(M zero, M one, std::int32_t count) {
  auto a = encode(zero);
  const auto b = encode(one);
  std::size_t k = 0;
  while (k < a.size() && k < b.size() && a[k] == b[k]) ++k;
  EXPECT_GE(k, 3u);
  const auto u = static_cast<std::uint32_t>(count);
  for (int i = 0; i < 4; ++i) a[k - 3 + i] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
  return a;
}

std::vector<std::uint8_t> huge_odometry() {
  odometry_t a{};
  a.position[0] = 0.25;
  odometry_t b = a;
  b.n_pose_cov = 1;
  b.pose_covariance = {0.0};
  return with_count(a, b, 150'000'000);
}

std::vector<std::uint8_t> huge_thruster_command() {
  thruster_command_t a{};
  a.armed = true;
  thruster_command_t b = a;
  b.n_thrusters = 1;
  b.names = {"x"};
  b.command = {0.0};
  // The first difference is n_thrusters' low byte (names follow it).
  return with_count(a, b, 50'000'000);
}

TEST(CountGuard, HugeCountsAndNegativeCountsAreRefused) {
  const auto o = huge_odometry();
  ASSERT_EQ(o.size(), 124u);  // 8 hash + 108 fixed + two int32 counts: no array bytes at all
  EXPECT_FALSE(counts_fit<odometry_t>(o.data(), static_cast<int>(o.size())));
  const auto t = huge_thruster_command();
  EXPECT_FALSE(counts_fit<thruster_command_t>(t.data(), static_cast<int>(t.size())));
  odometry_t a{};
  odometry_t b = a;
  b.n_pose_cov = 1;
  b.pose_covariance = {0.0};
  const auto neg = with_count(a, b, -1);
  EXPECT_FALSE(counts_fit<odometry_t>(neg.data(), static_cast<int>(neg.size())));
  // The largest count the bytes can hold still passes the guard (decode then checks exactly):
  // a count of 1 on a count-0 packet padded with 8 bytes.
  auto one = with_count(a, b, 1);
  one.insert(one.begin() + static_cast<std::ptrdiff_t>(one.size() - 4), 8, 0);
  EXPECT_TRUE(counts_fit<odometry_t>(one.data(), static_cast<int>(one.size())));
  EXPECT_FALSE(counts_fit<odometry_t>(one.data(), static_cast<int>(one.size() - 1)));
  // A string whose length is 0 (no NUL) or negative, or longer than the packet.
  arm_state_t s{};
  s.reason = "x";
  auto sb = encode(s);
  const std::size_t len_at = sb.size() - 2 - 4;  // int32 length, then "x\0"
  for (std::uint8_t bad : {0x00, 0xFF, 0x03}) {
    auto p = sb;
    for (int i = 0; i < 3; ++i) p[len_at + i] = bad == 0xFF ? 0xFF : 0;
    p[len_at + 3] = bad;
    EXPECT_FALSE(counts_fit<arm_state_t>(p.data(), static_cast<int>(p.size()))) << int(bad);
  }
  EXPECT_TRUE(counts_fit<arm_state_t>(sb.data(), static_cast<int>(sb.size())));
  EXPECT_FALSE(counts_fit<arm_state_t>(nullptr, 0));
}

class Receiver : public Node {
 public:
  Receiver() : Node("receiver", 100'000) {
    subscribe("TILLER_ODOMETRY", &Receiver::on_odometry);
    subscribe("TILLER_THRUSTER_COMMAND", &Receiver::on_command);
  }
  void on_odometry(const odometry_t& m, TimeUs) {
    x = m.position[0];
    ++odometry;
  }
  void on_command(const thruster_command_t& m, TimeUs) {
    commands = m.n_thrusters;
    ++command;
  }
  void on_tick(TimeUs) override {}
  double x = 0;
  int odometry = 0, command = 0, commands = -1;
};

TEST(CountGuard, CraftedPacketsAreMalformedAllocateNothingAndTheNextGoodOneIsHandled) {
  const auto o = huge_odometry();
  const auto t = huge_thruster_command();
  Receiver r;
  const long before = test::allocations();
  r.deliver("TILLER_ODOMETRY", o.data(), static_cast<int>(o.size()), 10);
  r.deliver("TILLER_THRUSTER_COMMAND", t.data(), static_cast<int>(t.size()), 20);
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << "heap allocations for two crafted packets";
  EXPECT_EQ(r.counter_value("malformed.TILLER_ODOMETRY"), 1);
  EXPECT_EQ(r.counter_value("malformed.TILLER_THRUSTER_COMMAND"), 1);
  EXPECT_EQ(r.odometry, 0);
  EXPECT_EQ(r.command, 0);
  EXPECT_FALSE(r.faulted());

  odometry_t good{};
  good.position[0] = 0.5;
  good.n_pose_cov = 36;
  good.pose_covariance.assign(36, 0.0);
  const auto g = encode(good);
  r.deliver("TILLER_ODOMETRY", g.data(), static_cast<int>(g.size()), 30);
  thruster_command_t cmd{};
  cmd.n_thrusters = 3;
  cmd.names = kNames;
  cmd.command = {0.1, 0.2, 0.3};
  const auto c = encode(cmd);
  r.deliver("TILLER_THRUSTER_COMMAND", c.data(), static_cast<int>(c.size()), 40);
  EXPECT_EQ(r.odometry, 1);
  EXPECT_DOUBLE_EQ(r.x, 0.5);
  EXPECT_EQ(r.command, 1);
  EXPECT_EQ(r.commands, 3);
  EXPECT_EQ(r.counter_value("malformed.TILLER_ODOMETRY"), 1);
  EXPECT_EQ(r.counter_value("malformed.TILLER_THRUSTER_COMMAND"), 1);

  // A truncated valid packet is refused too (counted, not handled).
  r.deliver("TILLER_THRUSTER_COMMAND", c.data(), static_cast<int>(c.size()) - 3, 50);
  EXPECT_EQ(r.command, 1);
  EXPECT_EQ(r.counter_value("malformed.TILLER_THRUSTER_COMMAND"), 2);
}

// Logs decode through tiller::decode(Event) (tiller-score, log summaries): same guard.
TEST(CountGuard, EventDecodeRefusesCraftedPacketsWithoutAllocating) {
  const Event bad{"TILLER_ODOMETRY", 0, huge_odometry()};
  const Event bad_cmd{"TILLER_THRUSTER_COMMAND", 0, huge_thruster_command()};
  odometry_t o{};
  thruster_command_t t{};
  const long before = test::allocations();
  const bool decoded = decode(bad, o) || decode(bad_cmd, t);
  EXPECT_EQ(test::allocations() - before, 0);
  EXPECT_FALSE(decoded);
  odometry_t good{};
  good.position[1] = 2.0;
  EXPECT_TRUE(decode(encode("TILLER_ODOMETRY", 0, good), o));
  EXPECT_DOUBLE_EQ(o.position[1], 2.0);
}

}  // namespace
}  // namespace tiller
