// Message checks (core/message_checks.hpp), table-driven: for every input type a good message
// passes, and perturbing each field in turn (NaN, infinity, just outside its documented range)
// gives the expected reason; values on the documented boundary pass.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/message_checks.hpp"

namespace tiller::checks {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

template <class Msg>
struct Case {
  std::string what;
  std::function<void(Msg&)> perturb;
  const char* reason;  // nullptr: still good
};

template <class Msg>
void run_table(const Msg& good, const std::vector<Case<Msg>>& cases) {
  EXPECT_EQ(check(good), nullptr) << "the good " << Msg::getTypeName() << " fails";
  for (const auto& c : cases) {
    Msg m = good;
    c.perturb(m);
    const char* got = check(m);
    EXPECT_STREQ(got ? got : "(ok)", c.reason ? c.reason : "(ok)")
        << Msg::getTypeName() << ": " << c.what;
  }
}

TEST(MessageChecks, Odometry) {
  odometry_t g{};
  g.position[0] = 12.0;
  g.orientation[2] = 1.0;
  g.velocity[0] = 0.5;
  std::vector<Case<odometry_t>> t;
  for (int i = 0; i < 3; ++i) {
    t.push_back({"position NaN " + std::to_string(i), [i](auto& m) { m.position[i] = kNan; },
                 "position.nan"});
    t.push_back({"position inf " + std::to_string(i), [i](auto& m) { m.position[i] = -kInf; },
                 "position.nan"});
    t.push_back({"orientation NaN " + std::to_string(i), [i](auto& m) { m.orientation[i] = kNan; },
                 "orientation.nan"});
  }
  for (int i = 0; i < 6; ++i)
    t.push_back({"velocity NaN " + std::to_string(i), [i](auto& m) { m.velocity[i] = kInf; },
                 "velocity.nan"});
  t.push_back({"yaw = pi", [](auto& m) { m.orientation[2] = kPi; }, nullptr});
  t.push_back({"valid all", [](auto& m) { m.valid = odometry_t::VALID_ALL; }, nullptr});
  t.push_back({"valid 31", [](auto& m) { m.valid = 31; }, nullptr});
  t.push_back({"valid 32", [](auto& m) { m.valid = 32; }, "valid.unknown"});
  t.push_back({"valid -1", [](auto& m) { m.valid = -1; }, "valid.unknown"});
  t.push_back({"yaw = -pi", [](auto& m) { m.orientation[2] = -kPi; }, "yaw.range"});
  t.push_back({"yaw = 4", [](auto& m) { m.orientation[2] = 4.0; }, "yaw.range"});
  t.push_back({"yaw just above -pi", [](auto& m) { m.orientation[2] = -kPi + 1e-12; }, nullptr});
  t.push_back({"roll = 3.5", [](auto& m) { m.orientation[0] = 3.5; }, "roll.range"});
  t.push_back({"roll = pi", [](auto& m) { m.orientation[0] = kPi; }, nullptr});
  t.push_back({"pitch = pi/2", [](auto& m) { m.orientation[1] = kPi / 2; }, nullptr});
  t.push_back({"pitch = 1.6", [](auto& m) { m.orientation[1] = 1.6; }, "pitch.range"});
  t.push_back({"pitch = -1.6", [](auto& m) { m.orientation[1] = -1.6; }, "pitch.range"});
  t.push_back({"pose cov 36",
               [](auto& m) {
                 m.n_pose_cov = 36;
                 m.pose_covariance.assign(36, 0.01);
               },
               nullptr});
  t.push_back({"pose cov 9",
               [](auto& m) {
                 m.n_pose_cov = 9;
                 m.pose_covariance.assign(9, 0.01);
               },
               "pose_cov.size"});
  t.push_back({"pose cov NaN",
               [](auto& m) {
                 m.n_pose_cov = 36;
                 m.pose_covariance.assign(36, 0.01);
                 m.pose_covariance[35] = kNan;
               },
               "pose_cov.nan"});
  t.push_back({"velocity cov 6",
               [](auto& m) {
                 m.n_velocity_cov = 6;
                 m.velocity_covariance.assign(6, 0.0);
               },
               "velocity_cov.size"});
  t.push_back({"velocity cov inf",
               [](auto& m) {
                 m.n_velocity_cov = 36;
                 m.velocity_covariance.assign(36, 0.0);
                 m.velocity_covariance[0] = kInf;
               },
               "velocity_cov.nan"});
  run_table(g, t);
}

TEST(MessageChecks, VelocitySetpoint) {
  velocity_setpoint_t g{};
  g.frame = velocity_setpoint_t::FRAME_BODY;
  g.velocity[0] = 1.0;
  g.heading_valid = true;
  g.target_heading = 0.5;
  g.active = true;
  std::vector<Case<velocity_setpoint_t>> t = {
      {"frame 2", [](auto& m) { m.frame = 2; }, "frame.unknown"},
      {"frame NED", [](auto& m) { m.frame = velocity_setpoint_t::FRAME_NED; }, nullptr},
      {"heading -pi", [](auto& m) { m.target_heading = -kPi; }, "heading.range"},
      {"heading 7 unused",
       [](auto& m) {
         m.heading_valid = false;
         m.target_heading = 7.0;
       },
       nullptr},
      {"heading NaN unused",
       [](auto& m) {
         m.heading_valid = false;
         m.target_heading = kNan;
       },
       "heading.nan"},
  };
  for (int i = 0; i < 3; ++i) {
    t.push_back({"velocity 10", [i](auto& m) { m.velocity[i] = 10.0; }, nullptr});
    t.push_back({"velocity -10.01", [i](auto& m) { m.velocity[i] = -10.01; }, "velocity.range"});
    t.push_back({"velocity NaN", [i](auto& m) { m.velocity[i] = kNan; }, "velocity.range"});
  }
  run_table(g, t);
}

TEST(MessageChecks, StationTarget) {
  station_target_t g{};
  g.active = true;
  g.position[0] = 3.0;
  g.heading_valid = true;
  g.heading = -1.0;
  std::vector<Case<station_target_t>> t = {
      {"heading pi", [](auto& m) { m.heading = kPi; }, nullptr},
      {"heading -4", [](auto& m) { m.heading = -4.0; }, "heading.range"},
      {"heading -4 unused",
       [](auto& m) {
         m.heading_valid = false;
         m.heading = -4.0;
       },
       nullptr},
      {"heading inf", [](auto& m) { m.heading = kInf; }, "heading.nan"},
  };
  for (int i = 0; i < 3; ++i)
    t.push_back({"position NaN", [i](auto& m) { m.position[i] = kNan; }, "position.nan"});
  run_table(g, t);
}

TEST(MessageChecks, Wrench) {
  wrench_t g{};
  g.source = wrench_t::SOURCE_VELOCITY_PID;
  g.valid = true;
  g.tau[0] = 100.0;
  std::vector<Case<wrench_t>> t = {
      {"source 6", [](auto& m) { m.source = 6; }, "source.unknown"},  // past SOURCE_FAILSAFE (5)
      {"source failsafe", [](auto& m) { m.source = wrench_t::SOURCE_FAILSAFE; }, nullptr},
      {"source -1", [](auto& m) { m.source = -1; }, "source.unknown"},
  };
  for (int i = 0; i < 6; ++i) {
    t.push_back({"tau 1e5", [i](auto& m) { m.tau[i] = 1e5; }, nullptr});
    t.push_back({"tau -1.0001e5", [i](auto& m) { m.tau[i] = -1.0001e5; }, "tau.range"});
    t.push_back({"tau NaN", [i](auto& m) { m.tau[i] = kNan; }, "tau.range"});
  }
  run_table(g, t);
}

TEST(MessageChecks, AllocationStatus) {
  allocation_status_t g{};
  g.source = wrench_t::SOURCE_STATION_KEEP;
  g.scale = 1.0;
  g.n_thrusters = 2;
  g.names = {"port", "starboard"};
  g.saturated = {false, true};
  std::vector<Case<allocation_status_t>> t = {
      {"source 9", [](auto& m) { m.source = 9; }, "source.unknown"},
      {"scale 0", [](auto& m) { m.scale = 0.0; }, nullptr},
      {"scale 1.01", [](auto& m) { m.scale = 1.01; }, "scale.range"},
      {"scale -0.1", [](auto& m) { m.scale = -0.1; }, "scale.range"},
      {"scale NaN", [](auto& m) { m.scale = kNan; }, "scale.range"},
      {"17 thrusters", [](auto& m) { m.n_thrusters = 17; }, "n_thrusters.range"},
  };
  for (int i = 0; i < 6; ++i) {
    t.push_back({"demanded NaN", [i](auto& m) { m.demanded[i] = kNan; }, "demanded.nan"});
    t.push_back({"achieved inf", [i](auto& m) { m.achieved[i] = kInf; }, "achieved.nan"});
    t.push_back({"unallocated NaN", [i](auto& m) { m.unallocated[i] = kNan; }, "unallocated.nan"});
  }
  run_table(g, t);
}

TEST(MessageChecks, Arbitration) {
  arbitration_t g{};
  g.mode = controller_mode_t::WAYPOINTING;
  g.active_source = wrench_t::SOURCE_STATION_KEEP;
  run_table(g, std::vector<Case<arbitration_t>>{
                   {"mode 9", [](auto& m) { m.mode = 9; }, nullptr},
                   {"mode 10", [](auto& m) { m.mode = 10; }, "mode.unknown"},
                   {"mode -1", [](auto& m) { m.mode = -1; }, "mode.unknown"},
                   {"source 6", [](auto& m) { m.active_source = 6; }, "source.unknown"},
                   {"source none", [](auto& m) { m.active_source = 0; }, nullptr},
               });
}

TEST(MessageChecks, ManualDemandAndVelocity) {
  manual_demand_t d{};
  d.valid = true;
  std::vector<Case<manual_demand_t>> td;
  for (int i = 0; i < 6; ++i) {
    td.push_back({"demand 1", [i](auto& m) { m.demand[i] = 1.0; }, nullptr});
    td.push_back({"demand -1.001", [i](auto& m) { m.demand[i] = -1.001; }, "demand.range"});
    td.push_back({"demand NaN", [i](auto& m) { m.demand[i] = kNan; }, "demand.range"});
  }
  run_table(d, td);

  manual_velocity_cmd_t v{};
  v.yaw_mode = manual_velocity_cmd_t::YAW_HEADING;
  v.valid = true;
  std::vector<Case<manual_velocity_cmd_t>> tv = {
      {"yaw mode 3", [](auto& m) { m.yaw_mode = 3; }, "yaw_mode.unknown"},
      {"yaw rate 5", [](auto& m) { m.yaw_rate = 5.0; }, nullptr},
      {"yaw rate 5.1", [](auto& m) { m.yaw_rate = 5.1; }, "yaw_rate.range"},
      {"heading -pi", [](auto& m) { m.heading = -kPi; }, "heading.range"},
      {"heading NaN", [](auto& m) { m.heading = kNan; }, "heading.range"},
      {"torque -1e4", [](auto& m) { m.yaw_torque = -1e4; }, nullptr},
      {"torque 2e4", [](auto& m) { m.yaw_torque = 2e4; }, "yaw_torque.range"},
  };
  for (int i = 0; i < 3; ++i)
    tv.push_back({"velocity 11", [i](auto& m) { m.velocity[i] = 11.0; }, "velocity.range"});
  run_table(v, tv);
}

TEST(MessageChecks, ModeArmPath) {
  controller_mode_t c{};
  run_table(c, std::vector<Case<controller_mode_t>>{
                   {"mode 2", [](auto& m) { m.mode = 2; }, nullptr},
                   {"mode 9", [](auto& m) { m.mode = 9; }, nullptr},
                   {"mode 10", [](auto& m) { m.mode = 10; }, "mode.unknown"},
               });
  EXPECT_EQ(check(arm_request_t{}), nullptr);
  EXPECT_EQ(check(arm_state_t{}), nullptr);

  path_t p{};
  p.n_waypoints = 2;
  p.waypoints.resize(2);
  p.waypoints[1].has_heading = true;
  p.waypoints[1].heading = kPi;
  run_table(p, std::vector<Case<path_t>>{
                   {"position 1e6", [](auto& m) { m.waypoints[0].position[0] = 1e6; }, nullptr},
                   {"position 2e6", [](auto& m) { m.waypoints[0].position[1] = 2e6; },
                    "waypoint.position.range"},
                   {"position NaN", [](auto& m) { m.waypoints[1].position[2] = kNan; },
                    "waypoint.position.range"},
                   {"heading -pi", [](auto& m) { m.waypoints[1].heading = -kPi; },
                    "waypoint.heading.range"},
                   {"heading NaN unused",
                    [](auto& m) {
                      m.waypoints[0].has_heading = false;
                      m.waypoints[0].heading = kNan;
                    },
                    nullptr},
                   {"10001 waypoints", [](auto& m) { m.n_waypoints = 10001; }, "n_waypoints.range"},
               });
}

TEST(MessageChecks, ProgressCommandsEscJoystick) {
  path_progress_t pp{};
  pp.segment = -1;
  run_table(pp, std::vector<Case<path_progress_t>>{
                    {"segment -2", [](auto& m) { m.segment = -2; }, "segment.range"},
                    {"xte NaN", [](auto& m) { m.cross_track_error = kNan; }, "error.nan"},
                    {"distance -1", [](auto& m) { m.distance_to_goal = -1; }, "distance.range"},
                    {"distance inf", [](auto& m) { m.distance_to_goal = kInf; }, "distance.range"},
                });

  path_speed_t ps{};
  ps.n_segments = 2;
  ps.speed = {0.0, 1.5};
  run_table(ps, std::vector<Case<path_speed_t>>{
                    {"speed -0.1", [](auto& m) { m.speed[0] = -0.1; }, "speed.range"},
                    {"speed 20.5", [](auto& m) { m.speed[1] = 20.5; }, "speed.range"},
                    {"speed NaN", [](auto& m) { m.speed[1] = kNan; }, "speed.range"},
                    {"count 3 of 2", [](auto& m) { m.n_segments = 3; }, "n_segments.range"},
                    {"count -1", [](auto& m) { m.n_segments = -1; }, "n_segments.range"},
                });

  datum_t dt{};
  dt.latitude = 59.437;
  dt.longitude = 10.6612;
  dt.altitude = 39.8;
  run_table(dt, std::vector<Case<datum_t>>{
                    {"latitude 90.5", [](auto& m) { m.latitude = 90.5; }, "latitude.range"},
                    {"latitude NaN", [](auto& m) { m.latitude = kNan; }, "latitude.range"},
                    {"longitude 180.5", [](auto& m) { m.longitude = 180.5; }, "longitude.range"},
                    {"altitude inf", [](auto& m) { m.altitude = kInf; }, "altitude.range"},
                    {"source 2", [](auto& m) { m.source = 2; }, "source.range"},
                });

  thruster_command_t tc{};
  tc.source = wrench_t::SOURCE_MANUAL_DEMAND;
  tc.n_thrusters = 2;
  tc.names = {"a", "b"};
  tc.command = {1.0, -1.0};
  run_table(tc, std::vector<Case<thruster_command_t>>{
                    {"command 1.01", [](auto& m) { m.command[1] = 1.01; }, "command.range"},
                    {"command NaN", [](auto& m) { m.command[0] = kNan; }, "command.range"},
                    {"source 7", [](auto& m) { m.source = 7; }, "source.unknown"},
                });

  esc_output_t eo{};
  eo.unit = esc_output_t::UNIT_PULSE_US;
  eo.n_channels = 1;
  eo.names = {"a"};
  eo.channel = {0};
  eo.value = {1500};
  eo.normalized = {0.0};
  run_table(eo, std::vector<Case<esc_output_t>>{
                    {"pulse 2500", [](auto& m) { m.value[0] = 2500; }, nullptr},
                    {"pulse 2501", [](auto& m) { m.value[0] = 2501; }, "value.range"},
                    {"throttle -32767",
                     [](auto& m) {
                       m.unit = esc_output_t::UNIT_THROTTLE_INT16;
                       m.value[0] = -32767;
                     },
                     nullptr},
                    {"throttle -32768",
                     [](auto& m) {
                       m.unit = esc_output_t::UNIT_THROTTLE_INT16;
                       m.value[0] = -32768;
                     },
                     "value.range"},
                    {"unit 2", [](auto& m) { m.unit = 2; }, "unit.unknown"},
                    {"normalized NaN", [](auto& m) { m.normalized[0] = kNan; }, "normalized.range"},
                });

  joystick_state_t js{};
  js.n_axes = 2;
  js.axes = {32767, -32767};
  run_table(js, std::vector<Case<joystick_state_t>>{
                    {"axis -32768", [](auto& m) { m.axes[1] = -32768; }, "axis.range"},
                    {"65 axes", [](auto& m) { m.n_axes = 65; }, "n_axes.range"},
                    {"129 buttons", [](auto& m) { m.n_buttons = 129; }, "n_buttons.range"},
                });
}

// A node decodes every message of a channel into one reused object, and lcm-gen's decode leaves
// an array of doubles as it was when its count is 0. The odometry check looks at the first
// `count` covariance entries only, so good odometry after one with a NaN covariance is not
// refused for the previous message's entries.
// GCC 12 at -O3 (Release) inlines lcm-gen's decode here and warns that its local msg_hash "may
// be used uninitialized"; the generated code returns before reading it when its decode fails,
// so this is one of the false positives the GCC manual warns -Wmaybe-uninitialized can give.
// Off for this function only; -Werror stays on.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
template <class Msg>
void decode_into(const Msg& from, Msg& target) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(from.getEncodedSize()));
  ASSERT_EQ(from.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  ASSERT_EQ(target.decode(buf.data(), 0, static_cast<int>(buf.size())),
            static_cast<int>(buf.size()));
}
#pragma GCC diagnostic pop

TEST(MessageChecks, ReusedDecodeTargetIsJudgedOnItsCountNotOnStaleEntries) {
  odometry_t bad{};
  bad.n_pose_cov = 36;
  bad.pose_covariance.assign(36, 0.0);
  bad.pose_covariance[3] = kNan;
  bad.n_velocity_cov = 36;
  bad.velocity_covariance.assign(36, kInf);
  odometry_t target{};
  decode_into(bad, target);
  EXPECT_STREQ(check(target), "pose_cov.nan");
  decode_into(odometry_t{}, target);              // no covariances
  EXPECT_EQ(target.pose_covariance.size(), 36u);  // lcm-gen left the stale entries
  EXPECT_EQ(check(target), nullptr);

  // A hand-made message whose array holds fewer entries than its count is refused.
  odometry_t short_cov{};
  short_cov.n_pose_cov = 36;
  short_cov.pose_covariance.assign(9, 0.0);
  EXPECT_STREQ(check(short_cov), "pose_cov.size");
}

}  // namespace
}  // namespace tiller::checks
