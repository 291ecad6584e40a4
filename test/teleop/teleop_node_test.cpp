// TeleopNode: shaping (deadzone continuity, expo), the presets' mapping and FRD signs, INIT
// events, unplug -> neutral at once, replug requires centring, debounced buttons, gain steps,
// modes, closed-loop manual velocity with heading hold, replay identity, bad input and config.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tiller/arm_state_t.hpp>
#include <tiller/heartbeat_t.hpp>
#include <tiller/manual_velocity_cmd_t.hpp>

#include "runtime/replay.hpp"
#include "teleop_rig.hpp"

namespace tiller {
namespace {

using test::config_path;
using test::Rig;

constexpr TimeUs ms(double v) {
  return static_cast<TimeUs>(v * 1000);
}

TEST(Shaping, DeadzoneIsContinuousAndFullAtFullDeflection) {
  for (double d : {0.0, 0.05, 0.08, 0.3}) {
    for (double e : {0.0, 0.3, 1.0}) {
      EXPECT_EQ(shape_axis(d, d, e), 0.0);
      EXPECT_EQ(shape_axis(-d * 0.5, d, e), 0.0);
      // Just past the edge the output is tiny: no step at the deadzone edge.
      EXPECT_LT(std::fabs(shape_axis(d + 1e-9, d, e)), 1e-8);
      EXPECT_LT(std::fabs(shape_axis(-d - 1e-9, d, e)), 1e-8);
      EXPECT_DOUBLE_EQ(shape_axis(1.0, d, e), 1.0);
      EXPECT_DOUBLE_EQ(shape_axis(-1.0, d, e), -1.0);
      // Monotonic and odd.
      double prev = -2;
      for (int i = -100; i <= 100; ++i) {
        const double x = i / 100.0;
        const double y = shape_axis(x, d, e);
        EXPECT_GE(y, prev);
        EXPECT_DOUBLE_EQ(y, -shape_axis(-x, d, e));
        prev = y;
      }
    }
  }
  // Hand computed: d = 0.1, e = 0.3, x = 0.55 -> s = 0.5 -> 0.7 * 0.5 + 0.3 * 0.125 = 0.3875.
  EXPECT_DOUBLE_EQ(shape_axis(0.55, 0.1, 0.3), 0.3875);
  EXPECT_DOUBLE_EQ(shape_axis(-0.55, 0.1, 0.0), -0.5);
}

TEST(Shaping, NormalisesJsUnits) {
  EXPECT_DOUBLE_EQ(normalise_axis(32767, false), 1.0);
  EXPECT_DOUBLE_EQ(normalise_axis(-32767, false), -1.0);
  EXPECT_DOUBLE_EQ(normalise_axis(-32768, false), -1.0);  // clamped
  EXPECT_DOUBLE_EQ(normalise_axis(0, false), 0.0);
  EXPECT_DOUBLE_EQ(normalise_axis(-32767, true), 0.0);  // trigger released
  EXPECT_DOUBLE_EQ(normalise_axis(0, true), 0.5);
  EXPECT_DOUBLE_EQ(normalise_axis(32767, true), 1.0);
}

TEST(Presets, AllLoad) {
  for (const char* f : {"extreme3dpro_seed000.yaml", "extreme3dpro_seed001.yaml",
                        "gamepad_xbox.yaml", "gamepad_blueboat.yaml"}) {
    EXPECT_NO_THROW(load_teleop_file(config_path(f))) << f;
  }
}

TEST(Mapping, Seed000StickForwardIsSurgeRightIsSway) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_positions.js");
  EXPECT_EQ(r.parser.init_events(), 18);  // 12 buttons + 6 axes
  auto at = [&](double t_ms) { return r.demand_at(ms(t_ms)); };
  // At plug-in (INIT, stick centred): valid at once, zero.
  EXPECT_TRUE(at(1000).valid);
  for (double v : at(1000).demand) EXPECT_EQ(v, 0.0);
  // Full forward: raw Y = -32767 -> +X (seed 000: jy = -axis1), nothing else.
  EXPECT_DOUBLE_EQ(at(1100).demand[0], 1.0);
  EXPECT_EQ(at(1100).demand[1], 0.0);
  // Half forward: seed 000 says half stick gives half throttle, so the preset is linear (expo 0);
  // x = 16384/32767, deadzone 0.05 rescaled: (x - 0.05) / 0.95 = 0.4737003 (hand computed).
  EXPECT_NEAR(at(1200).demand[0], 0.4737003, 1e-6);
  // Full right -> +Y only.
  EXPECT_EQ(at(1300).demand[0], 0.0);
  EXPECT_DOUBLE_EQ(at(1300).demand[1], 1.0);
  // Corner of the square: both full (the mixer maps the square onto what the thrusters can do).
  EXPECT_DOUBLE_EQ(at(1500).demand[0], 1.0);
  EXPECT_DOUBLE_EQ(at(1500).demand[1], 1.0);
  for (int i = 2; i < 6; ++i) EXPECT_EQ(at(1500).demand[i], 0.0);
  EXPECT_EQ(at(1600).demand[0], 0.0);
  // Each change was published at the instant of the event (not at the next tick).
  bool at_1100 = false;
  for (const auto& [t, m] : r.all<manual_demand_t>(channels::kManualDemand)) {
    if (t == ms(1100) && m.demand[0] == 1.0) at_1100 = true;
  }
  EXPECT_TRUE(at_1100);
}

TEST(Mapping, Seed001FiveDofSigns) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed001.yaml")));
  auto& s = r.plug_in({0, 0, 0, 32767, 0, 0});
  r.feed(ms(100));
  ASSERT_TRUE(r.node.centred());
  s.axes[2] = 32767;  // twist clockwise -> yaw clockwise (+N)
  r.feed(ms(200));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(200)).demand[5], 1.0);
  s.axes[2] = 0;
  s.axes[5] = -32767;  // hat up -> elevate up (-Z in FRD)
  r.feed(ms(300));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(300)).demand[2], -1.0);
  s.axes[5] = 32767;  // hat down -> descend (+Z)
  r.feed(ms(400));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(400)).demand[2], 1.0);
  s.axes[5] = 0;
  s.axes[1] = -32767;  // forward and strafe left
  s.axes[0] = -32767;
  r.feed(ms(500));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(500)).demand[0], 1.0);
  EXPECT_DOUBLE_EQ(r.demand_at(ms(500)).demand[1], -1.0);
  s.axes[0] = s.axes[1] = 0;
  s.buttons[4] = true;  // pitch nose up (+M), after the debounce
  r.feed(ms(600));
  r.run_until(ms(660));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(660)).demand[4], 1.0);
  s.buttons[4] = false;
  s.buttons[5] = true;  // nose down
  r.feed(ms(700));
  r.run_until(ms(760));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(760)).demand[4], -1.0);
  // The slider (axis 3, resting at full) is not mapped and never blocks centring.
}

TEST(Mapping, GamepadTriggersHeaveWithGain) {
  Rig r(load_teleop_file(config_path("gamepad_xbox.yaml")));
  r.play("xbox_triggers.js");
  // Triggers at rest (-32767) count as centred: valid at plug-in.
  EXPECT_TRUE(r.demand_at(ms(1000)).valid);
  EXPECT_EQ(r.demand_at(ms(1000)).demand[2], 0.0);
  // RT half: 0.5 normalised, d = 0.05, expo 0.3 -> 0.363464, x gain 0.75, elevate up (-Z).
  EXPECT_NEAR(r.demand_at(ms(1100)).demand[2], -0.2725980, 1e-6);
  EXPECT_DOUBLE_EQ(r.demand_at(ms(1200)).demand[2], 0.75);  // LT full -> descend
  EXPECT_DOUBLE_EQ(r.demand_at(ms(1300)).demand[0], 0.75);  // left stick up -> forward
  EXPECT_EQ(r.demand_at(ms(1300)).demand[2], 0.0);
}

TEST(Connection, InitDeflectedWaitsForCentre) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_init_deflected.js");
  EXPECT_FALSE(r.demand_at(ms(1000)).valid);
  EXPECT_FALSE(r.demand_at(ms(1199)).valid);
  for (const auto& [t, m] : r.all<manual_demand_t>(channels::kManualDemand)) {
    if (t < ms(1200)) {
      EXPECT_FALSE(m.valid);
      for (double v : m.demand) EXPECT_EQ(v, 0.0);  // no jump to the held deflection
    }
  }
  EXPECT_TRUE(r.demand_at(ms(1200)).valid);
  EXPECT_DOUBLE_EQ(r.demand_at(ms(1300)).demand[0], 1.0);
}

// Issue 12, finding 2: the start-up state arriving in two reads (a FIFO, a slow device) must not
// count the axis not yet reported as centred. Read 1: the buttons and axis 0 (sway, centred);
// read 2, 40 ms later: axis 1 (surge) held full forward. Before the fix the demand became valid
// after read 1 and jumped to full surge at read 2.
TEST(Connection, AxisNotYetReportedIsNotCentred) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  auto init = [](std::uint8_t type, std::uint8_t number, std::int16_t value) {
    return JsEvent{1000, value, static_cast<std::uint8_t>(type | kJsEventInit), number};
  };
  std::vector<JsEvent> first;
  for (std::uint8_t b = 0; b < 12; ++b) first.push_back(init(kJsEventButton, b, 0));
  first.push_back(init(kJsEventAxis, 0, 0));
  const std::vector<JsEvent> second = {init(kJsEventAxis, 1, -32767)};
  auto read = [&](const std::vector<JsEvent>& ev, TimeUs t) {
    r.parser.feed(reinterpret_cast<const std::uint8_t*>(ev.data()), ev.size() * sizeof(JsEvent),
                  r.state);
    r.state.connected = true;
    r.feed(t);
  };
  read(first, ms(1000));
  EXPECT_FALSE(r.demand_at(ms(1000)).valid);
  r.run_until(ms(1040));
  EXPECT_FALSE(r.demand_at(ms(1039)).valid);
  read(second, ms(1040));
  r.run_until(ms(3000));
  for (const auto& [t, m] : r.all<manual_demand_t>(channels::kManualDemand)) {
    EXPECT_FALSE(m.valid) << "at t = " << t << " us";
    for (double v : m.demand) EXPECT_EQ(v, 0.0) << "at t = " << t << " us";
  }
  // Centring the held axis makes the demand valid; pushing it again moves.
  r.state.axes[1] = 0;
  r.feed(ms(3000));
  EXPECT_TRUE(r.demand_at(ms(3000)).valid);
  r.state.axes[1] = -32767;
  r.feed(ms(3100));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(3100)).demand[0], 1.0);
}

TEST(Connection, UnplugGivesNeutralAtOnceAndReplugNeedsCentring) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_positions.js");
  // Hold full forward, then pull the plug at 1710 ms, between ticks.
  r.state.axes[1] = -32767;
  r.feed(ms(1700));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(1700)).demand[0], 1.0);
  r.unplug(ms(1710));
  const auto d = r.demand_at(ms(1710));  // published at the unplug instant itself
  EXPECT_FALSE(d.valid);
  for (double v : d.demand) EXPECT_EQ(v, 0.0);
  EXPECT_FALSE(r.node.connected());
  EXPECT_EQ(r.node.counter_value("joystick.disconnects"), 1);
  // The heartbeat says so at the same instant (not at the next 1 Hz heartbeat).
  bool hb_at_unplug = false;
  for (const auto& [t, m] : r.all<heartbeat_t>(r.node.heartbeat_channel())) {
    hb_at_unplug = hb_at_unplug || (t == ms(1710) && m.state == heartbeat_t::STATE_DEGRADED);
  }
  EXPECT_TRUE(hb_at_unplug);
  // Stays neutral on every tick while absent; the heartbeat says why.
  r.run_until(ms(3000));
  for (const auto& [t, m] : r.all<manual_demand_t>(channels::kManualDemand)) {
    if (t >= ms(1710)) {
      EXPECT_FALSE(m.valid);
    }
  }
  const auto hb = r.all<heartbeat_t>(r.node.heartbeat_channel());
  ASSERT_FALSE(hb.empty());
  EXPECT_EQ(hb.back().second.state, heartbeat_t::STATE_DEGRADED);
  EXPECT_NE(hb.back().second.status.find("joystick absent"), std::string::npos);
  // Replug with the stick held forward (the recorded deflected plug-in, 3 s later).
  r.play("e3dp_init_deflected.js", ms(3000));
  EXPECT_FALSE(r.demand_at(ms(4100)).valid);
  EXPECT_EQ(r.demand_at(ms(4100)).demand[0], 0.0);
  EXPECT_TRUE(r.demand_at(ms(4200)).valid);
  EXPECT_DOUBLE_EQ(r.demand_at(ms(4300)).demand[0], 1.0);
  r.run_until(ms(5100));
  EXPECT_EQ(r.all<heartbeat_t>(r.node.heartbeat_channel()).back().second.state,
            heartbeat_t::STATE_OK);
}

TEST(Buttons, DebouncedArmAndDisarm) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_buttons.js");
  r.run_until(ms(2000));
  const auto req = r.all<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(req.size(), 2u);  // the 5 ms pulses at 1100-1115 ms and the bounce at 1200 ignored
  EXPECT_TRUE(req[0].second.arm);
  // Held from 1206 ms: stable after 30 ms (1236), seen at the next tick (1240).
  EXPECT_EQ(req[0].first, ms(1240));
  EXPECT_EQ(req[0].second.source, "teleop");
  EXPECT_FALSE(req[1].second.arm);
  EXPECT_EQ(req[1].first, ms(1540));
  EXPECT_GE(r.node.counter_value("buttons.bounces_ignored"), 3);
}

TEST(Buttons, HeldAtPlugInDoesNotArm) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_init_button_held.js");
  r.run_until(ms(2000));
  const auto req = r.all<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(req.size(), 1u);
  EXPECT_EQ(req[0].first, ms(1440));  // the fresh press at 1400, not the INIT state at 1000
}

TEST(Buttons, PressLongerThanDebounceEndingBetweenTicksCounts) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));  // 30 ms, ticks every 20
  auto& s = r.plug_in();
  r.feed(ms(1000));
  s.buttons[6] = true;
  r.feed(ms(1001));
  s.buttons[6] = false;
  r.feed(ms(1035));  // held 34 ms; the ticks at 1020 saw only 19 ms
  r.run_until(ms(1200));
  const auto req = r.all<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(req.size(), 1u);
  EXPECT_EQ(req[0].first, ms(1035));
  // 29 ms is a bounce.
  s.buttons[6] = true;
  r.feed(ms(1301));
  s.buttons[6] = false;
  r.feed(ms(1330));
  r.run_until(ms(1500));
  EXPECT_EQ(r.all<arm_request_t>(channels::kArmRequest).size(), 1u);
}

TEST(Buttons, GainStepsModesAndTranslation) {
  TeleopParams p = load_teleop_file(config_path("extreme3dpro_seed000.yaml"));
  p.debounce = 0;
  Rig r(p);
  auto& s = r.plug_in();
  r.feed(ms(0));
  auto press = [&](int b, double t) {
    s.buttons[static_cast<std::size_t>(b)] = true;
    r.feed(ms(t));
    s.buttons[static_cast<std::size_t>(b)] = false;
    r.feed(ms(t + 50));
  };
  press(3, 100);  // gain down: 1.0 -> 0.75
  press(3, 200);  // 0.5
  press(3, 300);  // 0.25
  press(3, 400);  // stays at the minimum 0.25
  EXPECT_DOUBLE_EQ(r.node.gain(), 0.25);
  press(2, 500);  // gain up: 0.5
  EXPECT_DOUBLE_EQ(r.node.gain(), 0.5);
  s.axes[1] = -32767;
  r.feed(ms(600));
  EXPECT_DOUBLE_EQ(r.demand_at(ms(600)).demand[0], 0.5);
  s.axes[1] = 0;
  press(9, 700);   // closed-loop manual
  press(11, 800);  // is_translation on
  press(10, 900);  // autonomous
  auto modes = r.all<controller_mode_t>(channels::kMode);
  // The initial mode on the first tick, then one message per press (the 1 Hz repeat is not due
  // before 1 s).
  ASSERT_EQ(modes.size(), 4u);
  EXPECT_EQ(modes[0].first, 0);
  EXPECT_EQ(modes[0].second.mode, controller_mode_t::MANUAL_OPEN_LOOP);
  modes.erase(modes.begin());
  EXPECT_EQ(modes[0].second.mode, controller_mode_t::MANUAL_CLOSED_LOOP);
  EXPECT_FALSE(modes[0].second.is_translation);
  EXPECT_EQ(modes[1].second.mode, controller_mode_t::MANUAL_CLOSED_LOOP);
  EXPECT_TRUE(modes[1].second.is_translation);
  EXPECT_EQ(modes[2].second.mode, controller_mode_t::WAYPOINTING);
  EXPECT_TRUE(modes[2].second.is_translation);
  EXPECT_TRUE(r.all<arm_request_t>(channels::kArmRequest).empty());
}

TEST(Buttons, ModeIsPublishedAtStartAndRepeatedButArmIsNot) {
  // With no button pressed: the initial mode (config) goes out on the first tick and then every
  // mode_repeat (1 Hz), so a velocity PID started after the teleop learns the pilot's mode. An
  // arm request is never repeated (an ESC timeout disarm must not be undone by itself).
  TeleopParams p = load_teleop_file(config_path("extreme3dpro_seed000.yaml"));
  p.initial_mode = controller_mode_t::MANUAL_CLOSED_LOOP;
  p.debounce = 0;
  Rig r(p);
  auto& s = r.plug_in();
  r.feed(ms(0));
  s.buttons[6] = true;  // arm (base label 7)
  r.feed(ms(100));
  s.buttons[6] = false;
  r.feed(ms(150));
  r.run_until(ms(3500));
  const auto modes = r.all<controller_mode_t>(channels::kMode);
  ASSERT_EQ(modes.size(), 4u);  // 0, 1, 2, 3 s
  for (std::size_t k = 0; k < modes.size(); ++k) {
    EXPECT_EQ(modes[k].first, ms(1000.0 * static_cast<double>(k)));
    EXPECT_EQ(modes[k].second.mode, controller_mode_t::MANUAL_CLOSED_LOOP);
    EXPECT_EQ(modes[k].second.source, "teleop");
  }
  EXPECT_EQ(r.all<arm_request_t>(channels::kArmRequest).size(), 1u);

  p.mode_repeat = 0;  // mode_repeat_hz: 0 -> the initial mode once, then only on change
  Rig once(p);
  once.run_until(ms(3500));
  EXPECT_EQ(once.all<controller_mode_t>(channels::kMode).size(), 1u);
}

TEST(ClosedLoop, VelocityScaledAndHeadingHeld) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed001.yaml")));
  auto& s = r.plug_in({0, -32767, 0, 0, 0, 0});
  r.feed(ms(0));  // deflected at plug-in: invalid
  s.axes[1] = 0;
  r.feed(ms(10));
  odometry_t o{};
  // An ROV's estimate without a position source: heading hold needs the attitude only.
  o.valid = int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH};
  o.orientation[2] = 1.0;
  r.node.deliver(channels::kOdometry, nullptr, 0, ms(15));  // malformed: counted, ignored
  auto deliver_odom = [&](double t) {
    std::vector<std::uint8_t> b(static_cast<std::size_t>(o.getEncodedSize()));
    o.encode(b.data(), 0, static_cast<int>(b.size()));
    r.node.deliver(channels::kOdometry, b.data(), static_cast<int>(b.size()), ms(t));
  };
  deliver_odom(20);
  s.axes[1] = -32767;  // full forward, full twist clockwise
  s.axes[2] = 32767;
  r.feed(ms(30));
  auto last_vel = [&] {
    return r.all<manual_velocity_cmd_t>(channels::kManualVelocity).back().second;
  };
  manual_velocity_cmd_t v = last_vel();
  EXPECT_TRUE(v.valid);
  EXPECT_DOUBLE_EQ(v.velocity[0], 0.5);
  EXPECT_EQ(v.yaw_mode, manual_velocity_cmd_t::YAW_RATE);
  EXPECT_NEAR(v.yaw_rate, 30.0 * M_PI / 180.0, 1e-12);
  // Twist released: hold the heading seen at release, even when odometry then moves.
  o.orientation[2] = 1.2;
  deliver_odom(35);
  s.axes[2] = 0;
  r.feed(ms(40));
  o.orientation[2] = 1.3;
  deliver_odom(45);
  r.run_until(ms(60));
  v = last_vel();
  EXPECT_EQ(v.yaw_mode, manual_velocity_cmd_t::YAW_HEADING);
  EXPECT_DOUBLE_EQ(v.heading, 1.2);
  // Odometry without a valid attitude is not taken (counted); NaN odometry is dropped and counted.
  o.valid = odometry_t::VALID_DEPTH;
  o.orientation[2] = 2.0;
  deliver_odom(65);
  EXPECT_EQ(r.node.counter_value("odometry.invalid"), 1);
  o.orientation[2] = std::nan("");
  deliver_odom(70);
  EXPECT_EQ(r.node.counter_value("rejected.odometry.nan"), 1);
  // Stale odometry (> 0.5 s): no heading to hold, zero yaw rate instead.
  r.run_until(ms(700));
  v = last_vel();
  EXPECT_EQ(v.yaw_mode, manual_velocity_cmd_t::YAW_RATE);
  EXPECT_EQ(v.yaw_rate, 0.0);
}

TEST(Health, StatusShowsTheEscArmStateAndWhenItGoesSilent) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.play("e3dp_init_button_held.js");  // connected at 1000 ms, centred
  auto status = [&] { return r.all<heartbeat_t>(r.node.heartbeat_channel()).back().second.status; };
  r.run_until(ms(2000));
  EXPECT_NE(status().find("arm state unknown"), std::string::npos) << status();
  arm_state_t a{};
  a.armed = true;
  a.reason = "armed by teleop";
  std::vector<std::uint8_t> b(static_cast<std::size_t>(a.getEncodedSize()));
  for (int i = 0; i < 10; ++i) {  // 10 Hz for a second
    const TimeUs t = ms(2050 + 100 * i);
    a.utime = t;
    a.encode(b.data(), 0, static_cast<int>(b.size()));
    r.run_until(t);
    r.node.deliver(channels::kArmState, b.data(), static_cast<int>(b.size()), t);
  }
  r.run_until(ms(3000));
  EXPECT_NE(status().find("ARMED"), std::string::npos) << status();
  EXPECT_EQ(status().find("joystick ok"), 0u) << status();
  r.run_until(ms(4000));  // tiller-esc silent for 0.5 s and more
  EXPECT_NE(status().find("arm state unknown"), std::string::npos) << status();
}

TEST(Input, MalformedStateRejected) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  r.state.connected = true;
  r.state.n_axes = 3;  // but no axis values
  r.feed(ms(10));
  EXPECT_EQ(r.node.counter_value("rejected.joystick.malformed"), 1);
  EXPECT_FALSE(r.node.connected());
}

TEST(Input, ReusedDecodeTargetWithACountOfZeroIsNotMalformed) {
  // The replay path decodes every TILLER_JOYSTICK into one reused object; lcm-gen leaves the
  // arrays of the previous message in place when a count is 0, so only the first n entries may
  // count. A state with 0 axes after one with 6 is a valid (empty) state, not a malformed one.
  TeleopParams p = load_teleop_file(config_path("extreme3dpro_seed000.yaml"));
  TeleopNode node(p, TeleopNode::Input::replay);
  test::CollectBus bus;
  node.attach(&bus);
  joystick_state_t in{};
  in.device = "test";
  in.connected = true;
  in.n_axes = 6;
  in.axes = {0, -32767, 0, 0, 0, 0};
  in.n_buttons = 12;
  in.buttons.assign(12, false);
  joystick_state_t reused{};
  auto deliver = [&](TimeUs t) {
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(in.getEncodedSize()));
    in.encode(buf.data(), 0, static_cast<int>(buf.size()));
    ASSERT_EQ(reused.decode(buf.data(), 0, static_cast<int>(buf.size())),
              static_cast<int>(buf.size()));
    node.deliver(channels::kJoystick, buf.data(), static_cast<int>(buf.size()), t);
  };
  deliver(0);
  in.n_axes = 0;
  in.axes.clear();
  in.n_buttons = 0;
  in.buttons.clear();
  deliver(10'000);
  EXPECT_EQ(reused.axes.size(), 6u);  // what lcm-gen does: the stale array stays
  EXPECT_EQ(node.counter_value("rejected.joystick.malformed"), 0);
  node.attach(nullptr);
}

TEST(Replay, SameOutputsFromTheRecordedJoystickChannel) {
  const TeleopParams p = load_teleop_file(config_path("extreme3dpro_seed000.yaml"));
  Rig live(p);
  live.play("e3dp_positions.js");
  live.unplug(ms(1710));
  live.play("e3dp_init_deflected.js", ms(2000));
  live.play("e3dp_buttons.js", ms(4000));
  live.run_until(ms(6000));
  std::vector<Event> log;
  for (const Event& e : live.bus.events) {
    if (e.channel == channels::kJoystick) log.push_back(e);
  }
  TeleopNode replayed(p, TeleopNode::Input::replay);
  ReplayExecutor rx(replayed);
  rx.run(log, TimeUs{0}, ms(6000));
  auto pick = [](const std::vector<Event>& ev, const std::string& ch) {
    std::vector<Event> out;
    for (const Event& e : ev) {
      if (e.channel == ch) out.push_back(e);
    }
    return out;
  };
  for (const char* ch :
       {channels::kManualDemand, channels::kArmRequest, channels::kManualVelocity}) {
    ASSERT_FALSE(pick(live.bus.events, ch).empty()) << ch;
    const auto a = pick(live.bus.events, ch);
    const auto b = pick(rx.outputs(), ch);
    ASSERT_EQ(a.size(), b.size()) << ch;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].time, b[i].time) << ch << " " << i;
      EXPECT_EQ(a[i].data, b[i].data) << ch << " " << i;
    }
  }
}

TEST(Config, ErrorsNameKeyAndExpectation) {
  auto err = [](const std::string& text) {
    try {
      load_teleop(config::Value::parse(text, "t.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string ok_axes = "axes:\n  - {axis: 1, dof: surge, sign: -1}\n";
  EXPECT_EQ(err("device: {path: /dev/input/js0}\n" + ok_axes), "no error");
  EXPECT_NE(err("device: {}\n" + ok_axes).find("device"), std::string::npos);
  const std::string e1 = err("device: {path: x}\naxes:\n  - {axis: 1, dof: surge, sign: 2}\n");
  EXPECT_NE(e1.find("sign"), std::string::npos) << e1;
  EXPECT_NE(e1.find("t.yaml"), std::string::npos) << e1;
  EXPECT_NE(err("device: {path: x}\naxes:\n  - {axis: 1, dof: sideways, sign: 1}\n").find("dof"),
            std::string::npos);
  EXPECT_NE(err("device: {path: x}\n" + ok_axes + "deadzon: 0.1\n").find("deadzon"),
            std::string::npos);
  EXPECT_NE(err("device: {path: x}\n" + ok_axes + "buttons: {arm: 3, disarm: 3}\n").find("disarm"),
            std::string::npos);
  // One function per button: a press runs everything mapped to it.
  std::string e = err("device: {path: x}\n" + ok_axes + "buttons: {arm: 6, mode_open_loop: 6}\n");
  EXPECT_NE(e.find("t.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("buttons.mode_open_loop"), std::string::npos) << e;
  EXPECT_NE(e.find("not already used by buttons.arm (button 6)"), std::string::npos) << e;
  e = err("device: {path: x}\n" + ok_axes + "buttons: {disarm: 1, gain_up: 1}\n");
  EXPECT_NE(e.find("not already used by buttons.disarm"), std::string::npos) << e;
  e = err("device: {path: x}\n" + ok_axes +
          "buttons: {disarm: 1}\nbutton_axes:\n  - {dof: pitch, plus: 1, minus: 5}\n");
  EXPECT_NE(e.find("button_axes[0].plus"), std::string::npos) << e;
  EXPECT_NE(e.find("buttons.disarm"), std::string::npos) << e;
  e = err("device: {path: x}\n" + ok_axes + "button_axes:\n  - {dof: pitch, plus: 4, minus: 4}\n");
  EXPECT_NE(e.find("button_axes[0].minus"), std::string::npos) << e;
  EXPECT_NE(e.find("button_axes[0].plus"), std::string::npos) << e;
  EXPECT_NE(err("device: {path: x}\naxes:\n  - {axis: 1, dof: surge, sign: 1, deadzone: 0.95}\n")
                .find("deadzone"),
            std::string::npos);
}

// Issue 30, scenario 4: the joystick's start-up (INIT) events sent again after ordinary input
// while armed (a split, out-of-order INIT, as the kernel never sends it) put no thrust out: the
// demand goes neutral and invalid at once, a disarm request goes out, and the stick must be
// centred again. Before, the late INIT's full deflection became the demand.
TEST(LateInit, InitAfterInputGoesNeutralAsksToDisarmAndWaitsForCentre) {
  Rig r(load_teleop_file(config_path("extreme3dpro_seed000.yaml")));
  auto send = [&](TimeUs t, std::vector<JsEvent> ev) {
    r.parser.feed(reinterpret_cast<const std::uint8_t*>(ev.data()), ev.size() * sizeof(JsEvent),
                  r.state);
    r.state.connected = true;
    r.feed(t);
  };
  std::vector<JsEvent> init;
  for (std::uint8_t a = 0; a < 6; ++a) init.push_back({0, 0, kJsEventAxis | kJsEventInit, a});
  for (std::uint8_t b = 0; b < 12; ++b) init.push_back({0, 0, kJsEventButton | kJsEventInit, b});
  send(ms(100), init);
  send(ms(200), {{200, -16000, kJsEventAxis, 1}});  // the pilot pushes the stick
  const manual_demand_t moving = r.demand_at(ms(200));
  ASSERT_TRUE(moving.valid);
  double moved = 0;
  for (double d : moving.demand) moved = std::max(moved, std::abs(d));
  ASSERT_GT(moved, 0.3);
  EXPECT_EQ(r.state.late_inits, 0);
  // The late INIT: the device "re-reports" axis 1 at full deflection.
  send(ms(300), {{300, -32767, kJsEventAxis | kJsEventInit, 1}});
  EXPECT_EQ(r.state.late_inits, 1);
  EXPECT_EQ(r.node.counter_value("joystick.reinit"), 1);
  const manual_demand_t after = r.demand_at(ms(300));
  EXPECT_FALSE(after.valid);
  for (double d : after.demand) EXPECT_EQ(d, 0.0);
  const auto req = r.all<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(req.size(), 1u);
  EXPECT_EQ(req[0].first, ms(300));
  EXPECT_FALSE(req[0].second.arm);
  // Still deflected: neutral and invalid for as long as it is held.
  r.run_until(ms(800));
  for (const auto& [t, m] : r.all<manual_demand_t>(channels::kManualDemand)) {
    if (t <= ms(300)) continue;  // at 300 ms the tick (before the read) still had the push
    EXPECT_FALSE(m.valid) << t;
    for (double d : m.demand) EXPECT_EQ(d, 0.0) << t;
  }
  // Centred again: valid (and zero) again.
  send(ms(900), {{900, 0, kJsEventAxis, 1}});
  EXPECT_TRUE(r.demand_at(ms(900)).valid);
}

// The kernel's own order (every INIT first, in one read or split over several reads) is no late
// INIT, so a plug-in never disarms.
TEST(LateInit, SplitInitInTheKernelsOrderIsNotLate) {
  JsEventParser p;
  joystick_state_t s{};
  std::vector<JsEvent> first{{0, 0, kJsEventAxis | kJsEventInit, 0}};
  std::vector<JsEvent> rest{{0, 0, kJsEventAxis | kJsEventInit, 1},
                            {0, 0, kJsEventButton | kJsEventInit, 0},
                            {5, 100, kJsEventAxis, 0}};
  p.feed(reinterpret_cast<const std::uint8_t*>(first.data()), sizeof(JsEvent), s);
  p.feed(reinterpret_cast<const std::uint8_t*>(rest.data()), 3 * sizeof(JsEvent), s);
  EXPECT_EQ(s.late_inits, 0);
  EXPECT_EQ(p.init_events(), 3);
  std::vector<JsEvent> late{{6, 0, kJsEventButton | kJsEventInit, 0}};
  p.feed(reinterpret_cast<const std::uint8_t*>(late.data()), sizeof(JsEvent), s);
  EXPECT_EQ(s.late_inits, 1);
  EXPECT_EQ(p.late_init_events(), 1);
}

// Issue 30, the refusal display: the vehicle's reason and the station in control are in the
// teleop's status at once (a heartbeat published on the change), whatever the clock skew
// (the arm state is fresh by arrival: here stamped 0.7 s behind this station's clock).
TEST(VehicleReason, ShownAtOnceWithTheControllerWhateverTheSkew) {
  TeleopParams p = load_teleop_file(config_path("extreme3dpro_seed000.yaml"));
  p.station = "B";
  Rig r(p);
  r.plug_in();
  r.feed(ms(100));
  arm_state_t a{};
  a.utime = ms(1000) - 700'000;
  a.armed = true;
  a.session = 1;
  a.boot_nonce = 99;
  a.controller = "A";
  a.reason = "arm refused (asked by teleop at station B): another station in control: A";
  r.run_until(ms(1000));
  r.bus.now = ms(1000);
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(a.getEncodedSize()));
  a.encode(buf.data(), 0, static_cast<int>(buf.size()));
  r.node.deliver(channels::kArmState, buf.data(), static_cast<int>(buf.size()), ms(1000));
  const auto hbs = r.all<heartbeat_t>(r.node.heartbeat_channel());
  ASSERT_FALSE(hbs.empty());
  EXPECT_EQ(hbs.back().first, ms(1000));
  EXPECT_NE(hbs.back().second.status.find("ARMED (station A in control); vehicle: arm refused "
                                          "(asked by teleop at station B): another station in "
                                          "control: A"),
            std::string::npos)
      << hbs.back().second.status;
  EXPECT_TRUE(r.node.arm_known());
  r.run_until(ms(1400));  // 0.4 s later, no new arm state: still known (fresh by arrival)
  EXPECT_TRUE(r.node.arm_known());
  // The vehicle's clock 0.7 s ahead of this station's: still shown.
  a.utime = ms(1400) + 700'000;
  a.reason = "armed by teleop at station A";
  buf.resize(static_cast<std::size_t>(a.getEncodedSize()));
  a.encode(buf.data(), 0, static_cast<int>(buf.size()));
  r.node.deliver(channels::kArmState, buf.data(), static_cast<int>(buf.size()), ms(1400));
  EXPECT_EQ(r.node.vehicle_reason(), "armed by teleop at station A");
  EXPECT_TRUE(r.node.armed());
  EXPECT_EQ(r.node.counter_value("rejected.arm_state.skew"), 0);
  // Its arm requests carry that nonce and this station.
  r.state.buttons[static_cast<std::size_t>(p.buttons.arm)] = true;
  r.feed(ms(1410));
  r.run_until(ms(1500));
  const auto req = r.all<arm_request_t>(channels::kArmRequest);
  ASSERT_EQ(req.size(), 1u);
  EXPECT_EQ(req[0].second.boot_nonce, 99);
  EXPECT_EQ(req[0].second.station, "B");
  EXPECT_FALSE(req[0].second.takeover);
}

}  // namespace
}  // namespace tiller
