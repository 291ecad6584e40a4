// failsafe::Monitor's rules on hand-computed sequences (lib/failsafe/monitor.hpp): each rule's
// threshold, trigger time, hysteresis and latching; the action order; the config loader's
// errors (file, key, expected).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/config.hpp"
#include "failsafe/failsafe_config.hpp"
#include "failsafe/monitor.hpp"

namespace tiller::failsafe {
namespace {

constexpr TimeUs kTick = 100'000;  // 10 Hz

TimeUs at(double s) {
  return from_seconds(s);
}

MonitorParams battery_params() {
  MonitorParams p;
  p.battery.enabled = true;
  p.battery.warn_v = 14.0;
  p.battery.critical_v = 13.2;
  p.battery.hysteresis_v = 0.2;
  p.battery.trigger = at(2.0);
  p.battery.critical_action = Action::kHold;
  p.battery.disarm_after = at(30.0);
  return p;
}

// Feeds voltage(t) at 10 Hz from t0 to t1 (inclusive of t0), stepping after each reading; returns
// the first time `bit` is latched (-1 if never).
template <class F>
double first_latched(Monitor& m, double t0, double t1, std::int32_t bit, F voltage) {
  double first = -1;
  for (TimeUs t = at(t0); t <= at(t1); t += kTick) {
    m.on_power(voltage(to_seconds(t)), t);
    const Status& s = m.step(t);
    if ((s.latched & bit) != 0 && first < 0) first = to_seconds(t);
  }
  return first;
}

TEST(Battery, WarnAfterTriggerTimeBelowTheLevel) {
  Monitor m(battery_params());
  // 14.5 V until 1 s, then 13.9 V (below 14.0): warn 2 s later, at 3.0 s.
  const double t =
      first_latched(m, 0, 6, kBatteryWarn, [](double s) { return s < 1.0 ? 14.5 : 13.9; });
  EXPECT_DOUBLE_EQ(t, 3.0);
  EXPECT_EQ(m.status().action, Action::kWarn);
  EXPECT_EQ(m.status().latched & kBatteryCritical, 0);
  EXPECT_STREQ(m.status().reason, "battery low: 13.90 V < warning 14.00 V");
}

TEST(Battery, ReadingsBetweenTheLevelAndTheHysteresisDoNotRestartTheTimer) {
  Monitor m(battery_params());
  // Below at 1.0 s; 14.1 V (above 14.0 but not above 14.2) at 1.5 - 2.0 s: the timer runs on.
  const double t = first_latched(m, 0, 6, kBatteryWarn, [](double s) {
    if (s < 1.0) return 14.5;
    if (s >= 1.5 && s <= 2.0) return 14.1;
    return 13.9;
  });
  EXPECT_DOUBLE_EQ(t, 3.0);
}

TEST(Battery, AReadingAboveTheHysteresisRestartsTheTimer) {
  Monitor m(battery_params());
  // Below at 1.0 s; 14.3 V (> 14.2) at 2.0 s restarts; below again from 2.1 s: warn at 4.1 s.
  const double t = first_latched(m, 0, 8, kBatteryWarn, [](double s) {
    if (s < 1.0) return 14.5;
    if (std::fabs(s - 2.0) < 1e-9) return 14.3;
    return 13.9;
  });
  EXPECT_NEAR(t, 4.1, 1e-9);
}

TEST(Battery, FlickeringAroundTheLevelLatchesOnceAndStays) {
  Monitor m(battery_params());
  // 13.95 / 14.15 alternating every reading: never above 14.2, so the timer runs: warn at 2.0 s;
  // back at 15 V afterwards it stays latched (active too).
  const double t = first_latched(
      m, 0, 4, kBatteryWarn, [](double s) { return (std::lround(s * 10) % 2) ? 14.15 : 13.95; });
  EXPECT_DOUBLE_EQ(t, 2.0);
  first_latched(m, 4.1, 10, kBatteryWarn, [](double) { return 15.0; });
  EXPECT_NE(m.status().active & kBatteryWarn, 0);
  EXPECT_EQ(m.status().action, Action::kWarn);
}

TEST(Battery, CriticalHoldsThenDisarmsAfterItsTime) {
  Monitor m(battery_params());
  // 13.0 V from 10 s: warn and critical both below from 10 s, latched at 12.0 s; HOLD; DISARM
  // 30 s later, at 42.0 s. A recovery to 14.8 V (a pack resting) changes nothing.
  const double t =
      first_latched(m, 0, 20, kBatteryCritical, [](double s) { return s < 10.0 ? 15.0 : 13.0; });
  EXPECT_DOUBLE_EQ(t, 12.0);
  EXPECT_EQ(m.status().action, Action::kHold);
  EXPECT_NE(m.status().active & kBatteryWarn, 0);
  double disarm_at = -1;
  for (TimeUs tt = at(20.1); tt <= at(45); tt += kTick) {
    m.on_power(14.8, tt);
    if (m.step(tt).action == Action::kDisarm && disarm_at < 0) disarm_at = to_seconds(tt);
  }
  EXPECT_NEAR(disarm_at, 42.0, 1e-9);
  EXPECT_STREQ(m.status().reason, "battery critical (13.00 V < 13.20 V), then 30 s: disarmed");
}

TEST(Battery, StaleReadingsNeverTrigger) {
  MonitorParams p = battery_params();
  p.battery.stale = at(2.0);
  Monitor m(p);
  m.on_power(12.0, 0);  // one low reading, then silence
  for (TimeUs t = 0; t <= at(10); t += kTick) m.step(t);
  // Below from 0 s; fresh until 2.0 s, where the trigger time is just reached: latched at 2.0 s
  // exactly. A reading that went stale before its trigger time never latches:
  EXPECT_NE(m.status().latched & kBatteryCritical, 0);
  MonitorParams q = battery_params();
  q.battery.stale = at(1.0);
  Monitor m2(q);
  m2.on_power(12.0, 0);
  for (TimeUs t = 0; t <= at(10); t += kTick) m2.step(t);
  EXPECT_EQ(m2.status().latched, 0);
  EXPECT_EQ(m2.status().action, Action::kNone);
}

MonitorParams leak_params(Action a) {
  MonitorParams p;
  p.leak.enabled = true;
  p.leak.action = a;
  p.leak.trigger = at(0.5);
  return p;
}

TEST(Leak, WetForTheTriggerTimeLatchesItsAction) {
  Monitor m(leak_params(Action::kSurface));
  double first = -1;
  for (TimeUs t = 0; t <= at(10); t += kTick) {
    const double s = to_seconds(t);
    // A drop at 2.0 s only (shorter than 0.5 s): nothing; wet from 5.0 s to 6.0 s: latched at
    // 5.5 s, and it stays after the probe dries.
    m.on_leak(std::fabs(s - 2.0) < 1e-9 || (s >= 5.0 - 1e-9 && s <= 6.0 + 1e-9), t);
    if ((m.step(t).latched & kLeak) != 0 && first < 0) first = s;
  }
  EXPECT_NEAR(first, 5.5, 1e-9);
  EXPECT_EQ(m.status().action, Action::kSurface);
  EXPECT_NE(m.status().active & kLeak, 0);
  EXPECT_STREQ(m.status().reason, "leak: a probe is wet");
}

TEST(Leak, DisarmByConfig) {
  Monitor m(leak_params(Action::kDisarm));
  for (TimeUs t = 0; t <= at(1); t += kTick) {
    m.on_leak(true, t);
    m.step(t);
  }
  EXPECT_EQ(m.status().action, Action::kDisarm);
}

TEST(Leak, SurfaceThenDisarmAfterItsTime) {
  MonitorParams p = leak_params(Action::kSurface);
  p.leak.trigger = 0;
  p.leak.disarm_after = at(20);
  Monitor m(p);
  double disarm_at = -1;
  for (TimeUs t = 0; t <= at(30); t += kTick) {
    m.on_leak(t >= at(1), t);
    if (m.step(t).action == Action::kDisarm && disarm_at < 0) disarm_at = to_seconds(t);
  }
  EXPECT_NEAR(disarm_at, 21.0, 1e-9);
}

MonitorParams gnss_params() {
  MonitorParams p;
  p.gnss.enabled = true;
  p.gnss.lost_after = at(5);
  p.gnss.recover = at(2);
  p.gnss.stale = at(1);
  p.gnss.min_fix = 2;  // FIX_3D
  p.gnss.max_std_m = 5;
  p.gnss.action = Action::kNeutral;
  return p;
}

TEST(Gnss, LostAfterTheLimitSinceTheLastGoodFixThenRecovers) {
  Monitor m(gnss_params());
  double lost_at = -1, back_at = -1;
  for (TimeUs t = 0; t <= at(30); t += kTick) {
    const double s = to_seconds(t);
    // 3D fixes at 10 Hz until 10.0 s; 2D fixes (below min_fix) until 14 s; 3D with 8 m std
    // (above max_std_m) until 20 s; then good again. Last good: 10.0 s -> lost at 15.0 s.
    // Good from 20.0 s, unbroken: back at 22.0 s.
    if (s <= 10.0 + 1e-9)
      m.on_gnss(2, 1.0, t);
    else if (s < 14.0)
      m.on_gnss(1, 1.0, t);
    else if (s < 20.0 - 1e-9)
      m.on_gnss(2, 8.0, t);
    else
      m.on_gnss(2, 1.0, t);
    const Status& st = m.step(t);
    if ((st.active & kGnssLost) != 0 && lost_at < 0) lost_at = s;
    if (lost_at >= 0 && (st.active & kGnssLost) == 0 && back_at < 0) back_at = s;
  }
  EXPECT_NEAR(lost_at, 15.0, 1e-9);
  EXPECT_NEAR(back_at, 22.0, 1e-9);
  EXPECT_NE(m.status().latched & kGnssLost, 0);  // seen since start
  EXPECT_EQ(m.status().action, Action::kNone);
}

TEST(Gnss, NoFixAtAllIsLostAfterTheLimitFromStart) {
  Monitor m(gnss_params());
  Action at_4 = Action::kNone, at_5 = Action::kNone;
  for (TimeUs t = 0; t <= at(6); t += kTick) {
    const Status& s = m.step(t);
    if (t == at(4.9)) at_4 = s.action;
    if (t == at(5.0)) at_5 = s.action;
  }
  EXPECT_EQ(at_4, Action::kNone);
  EXPECT_EQ(at_5, Action::kNeutral);
  EXPECT_STREQ(m.status().reason, "GNSS lost: no good fix for 5.0 s");
}

TEST(Gnss, AFixEveryFewSecondsDoesNotRecover) {
  // Lost, then one good fix every 1.5 s (each more than stale_s = 1 s after the one before):
  // never 2 s of unbroken good input, so still lost.
  Monitor m(gnss_params());
  for (TimeUs t = 0; t <= at(30); t += kTick) {
    if (t > at(10) && (t / kTick) % 15 == 0) m.on_gnss(2, 1.0, t);
    m.step(t);
  }
  EXPECT_NE(m.status().active & kGnssLost, 0);
}

TEST(Gnss, OdometryPositionValidity) {
  MonitorParams p = gnss_params();
  p.gnss.use_fix = false;
  p.gnss.use_odometry = true;
  Monitor m(p);
  double lost_at = -1;
  for (TimeUs t = 0; t <= at(20); t += kTick) {
    m.on_odometry(0, 0, 0, 0, 0, t <= at(8), true, t);  // position flagged invalid after 8 s
    if ((m.step(t).active & kGnssLost) != 0 && lost_at < 0) lost_at = to_seconds(t);
  }
  EXPECT_NEAR(lost_at, 13.0, 1e-9);
  EXPECT_STREQ(m.status().reason, "position lost: no valid odometry position for 5.0 s");
}

TEST(Geofence, SignedDistanceAndNormal) {
  const std::vector<Point> sq = {{0, 0}, {0, 100}, {100, 100}, {100, 0}};
  double nn = 0, ne = 0;
  EXPECT_DOUBLE_EQ(signed_distance(sq, {50, 50}, &nn, &ne), 50.0);
  EXPECT_DOUBLE_EQ(signed_distance(sq, {90, 50}, &nn, &ne), 10.0);
  EXPECT_DOUBLE_EQ(nn, 1.0);  // nearest edge north = 100: outward is +north
  EXPECT_DOUBLE_EQ(ne, 0.0);
  EXPECT_DOUBLE_EQ(signed_distance(sq, {103, 50}, &nn, &ne), -3.0);
  EXPECT_DOUBLE_EQ(nn, 1.0);
  EXPECT_DOUBLE_EQ(signed_distance(sq, {-3, -4}, &nn, &ne), -5.0);  // beyond a corner
  EXPECT_DOUBLE_EQ(nn, -0.6);
  EXPECT_DOUBLE_EQ(ne, -0.8);
  EXPECT_DOUBLE_EQ(signed_distance(sq, {100, 50}, &nn, &ne), 0.0);  // on the edge
  EXPECT_DOUBLE_EQ(nn, 1.0);
  // The other winding gives the same.
  const std::vector<Point> cw = {{0, 0}, {100, 0}, {100, 100}, {0, 100}};
  EXPECT_DOUBLE_EQ(signed_distance(cw, {90, 50}, &nn, &ne), 10.0);
  EXPECT_DOUBLE_EQ(nn, 1.0);
}

MonitorParams fence_params() {
  MonitorParams p;
  p.geofence.enabled = true;
  p.geofence.polygon = {{0, 0}, {0, 100}, {100, 100}, {100, 0}};
  p.geofence.margin_m = 1.0;
  p.geofence.lookahead_s = 2.0;
  return p;
}

TEST(Geofence, HoldsWhenTheLookaheadReachesTheMarginMovingOutward) {
  Monitor m(fence_params());
  // North at 1.5 m/s from n = 80: the point 2 s ahead (+3 m) is within 1 m of n = 100 when
  // n > 96, i.e. from 16 / 1.5 = 10.67 s: the step at 10.7 s (n = 96.05).
  double hold_at = -1;
  for (TimeUs t = 0; t <= at(12); t += kTick) {
    const double n = 80 + 1.5 * to_seconds(t);
    m.on_odometry(n, 50, 0, 1.5, 0, true, true, t);
    if (m.step(t).action == Action::kHold && hold_at < 0) hold_at = to_seconds(t);
  }
  EXPECT_NEAR(hold_at, 10.7, 1e-9);
  // Stopped at n = 98.5 (inside the margin? no: 1.5 m from the edge): the hold stays (latched)
  // until the operator's go.
  for (TimeUs t = at(12.1); t <= at(20); t += kTick) {
    m.on_odometry(98.5, 50, 0, 0, 0, true, true, t);
    m.step(t);
  }
  EXPECT_EQ(m.status().action, Action::kHold);
  EXPECT_EQ(m.status().active & kGeofence, 0);  // 1.5 m inside: not near
  EXPECT_NE(m.status().latched & kGeofence, 0);
  m.on_operator_go(at(20));
  EXPECT_EQ(m.step(at(20.1)).action, Action::kNone);
  // Moving inward (south) from there: no hold. Outward again: at once.
  m.on_odometry(98.5, 50, 0, -1.0, 0, true, true, at(20.2));
  EXPECT_EQ(m.step(at(20.2)).action, Action::kNone);
  m.on_odometry(98.5, 50, 0, 0.5, 0, true, true, at(20.3));
  EXPECT_EQ(m.step(at(20.3)).action, Action::kHold);
}

TEST(Geofence, OutsideIsAnEventAndMovingFurtherOutHolds) {
  Monitor m(fence_params());
  m.on_odometry(105, 50, 0, 0, 0, true, true, 0);
  const Status& s = m.step(0);
  EXPECT_NE(s.active & kGeofence, 0);
  EXPECT_EQ(s.action, Action::kNone);  // at rest outside: reported; it may come back in
  EXPECT_STREQ(s.reason, "geofence: 5.0 m outside");
  m.on_odometry(105, 50, 0, 0.2, 0, true, true, at(0.1));
  EXPECT_EQ(m.step(at(0.1)).action, Action::kHold);
  EXPECT_STREQ(m.status().reason, "geofence: 5.0 m outside, holding (a START or RESUME ends it)");
}

TEST(Geofence, SlowDriftBelowTheOutwardSpeedIsNotAHold) {
  Monitor m(fence_params());
  m.on_odometry(99.5, 50, 0, 0.04, 0, true, true, 0);  // within the margin, 0.04 m/s < 0.05
  EXPECT_EQ(m.step(0).action, Action::kNone);
  EXPECT_NE(m.status().active & kGeofence, 0);
}

// A position flagged invalid (VALID_POSITION clear: GNSS lost past the estimator's uncertainty
// limit; its numbers are whatever the estimator last had) is no reading for the fence: it neither
// starts a hold nor, once the vehicle is holding, counts as the vehicle being back inside. The old
// rule took the numbers: it held on an invalid 99.5 m moving out, and an invalid point far inside
// cleared "near the fence". The GNSS-lost rule acts on the loss itself.
TEST(Geofence, AnInvalidPositionIsNoReadingAndKeepsTheLastVerdict) {
  Monitor m(fence_params());
  m.on_odometry(50, 50, 0, 0, 0, true, true, 0);
  EXPECT_EQ(m.step(0).action, Action::kNone);
  EXPECT_TRUE(m.position_known());
  m.on_odometry(99.5, 50, 0, 1.5, 0, false, true, at(0.1));  // invalid, at the fence moving out
  EXPECT_EQ(m.step(at(0.1)).action, Action::kNone);
  EXPECT_FALSE(m.position_known());
  EXPECT_EQ(m.status().latched & kGeofence, 0);
  // A valid position moving out within the margin: hold (near). Then invalid numbers far inside
  // at rest: the hold and "near" stay.
  m.on_odometry(99.5, 50, 0, 1.5, 0, true, true, at(0.2));
  EXPECT_EQ(m.step(at(0.2)).action, Action::kHold);
  m.on_odometry(10, 50, 0, 0, 0, false, true, at(0.3));
  EXPECT_EQ(m.step(at(0.3)).action, Action::kHold);
  EXPECT_NE(m.status().active & kGeofence, 0);
  EXPECT_STREQ(m.status().reason, "geofence: 0.5 m inside, holding (a START or RESUME ends it)");
}

TEST(Depth, RiseBelowTheLimitUntilAboveItMinusTheHysteresis) {
  MonitorParams p;
  p.depth.enabled = true;
  p.depth.limit_m = 10;
  p.depth.hysteresis_m = 0.5;
  Monitor m(p);
  auto at_depth = [&](double d, double s) {
    m.on_odometry(0, 0, d, 0, 0, true, true, at(s));
    return m.step(at(s)).action;
  };
  EXPECT_EQ(at_depth(9.9, 0), Action::kNone);
  EXPECT_EQ(at_depth(10.0, 1), Action::kNone);  // at the limit: not deeper
  EXPECT_EQ(at_depth(10.01, 2), Action::kRise);
  EXPECT_EQ(at_depth(9.6, 3), Action::kRise);  // within the hysteresis: still rising
  EXPECT_EQ(at_depth(9.49, 4), Action::kNone);
  EXPECT_NE(m.status().latched & kDepthLimit, 0);
}

// An invalid depth (VALID_DEPTH clear: a lost pressure sensor; its number is whatever the
// estimator last had) is no reading: no rise starts on it, and a rise in force goes on until a
// valid depth says the vehicle is above the limit less the hysteresis. The old rule took the
// number: it rose on the invalid 50 m and stopped on the invalid 0 m.
TEST(Depth, AnInvalidDepthIsUnknownAndKeepsTheLastVerdict) {
  MonitorParams p;
  p.depth.enabled = true;
  p.depth.limit_m = 10;
  p.depth.hysteresis_m = 0.5;
  Monitor m(p);
  auto at_depth = [&](double d, bool valid, double s) {
    m.on_odometry(0, 0, d, 0, 0, true, valid, at(s));
    return m.step(at(s)).action;
  };
  EXPECT_EQ(at_depth(9.0, true, 0), Action::kNone);
  EXPECT_EQ(at_depth(50.0, false, 1), Action::kNone);  // garbage: no rise
  EXPECT_FALSE(m.depth_known());
  EXPECT_EQ(m.status().latched & kDepthLimit, 0);
  EXPECT_EQ(at_depth(10.5, true, 2), Action::kRise);
  EXPECT_TRUE(m.depth_known());
  EXPECT_EQ(at_depth(0.0, false, 3), Action::kRise);  // unknown: still rising
  EXPECT_STREQ(m.status().reason, "depth unknown (last 10.5 m > limit 10.0 m): rising");
  EXPECT_EQ(at_depth(9.4, true, 4), Action::kNone);
}

TEST(Order, TheMostSevereActionWinsAndItsReasonIsGiven) {
  MonitorParams p = battery_params();
  p.leak = leak_params(Action::kSurface).leak;
  p.depth.enabled = true;
  p.depth.limit_m = 10;
  Monitor m(p);
  for (TimeUs t = 0; t <= at(3); t += kTick) {
    m.on_power(13.0, t);
    m.on_odometry(0, 0, 12, 0, 0, true, true, t);
    m.step(t);
  }
  EXPECT_EQ(m.status().action, Action::kRise);  // battery critical HOLD < RISE
  EXPECT_STREQ(m.status().reason, "depth 12.0 m > limit 10.0 m: rising");
  m.on_leak(true, at(3.1));
  m.step(at(3.1));
  m.on_leak(true, at(3.6));
  m.step(at(3.6));
  EXPECT_EQ(m.status().action, Action::kSurface);
  EXPECT_EQ(m.status().active, kBatteryWarn | kBatteryCritical | kLeak | kDepthLimit);
}

std::string load_error(const std::string& text) {
  try {
    load_failsafe_params(config::Value::parse(text, "failsafe.yaml"));
  } catch (const config::Error& e) {
    return e.what();
  }
  return "";
}

TEST(Config, ShippedFilesLoad) {
  for (const char* f : {"config/failsafe/otter.yaml", "config/failsafe/seed001_rov6.yaml"}) {
    const auto p = load_failsafe_file(std::string(TILLER_SOURCE_DIR) + "/" + f);
    EXPECT_TRUE(p.monitor.battery.enabled) << f;
  }
}

TEST(Config, ErrorsNameTheFileTheKeyAndWhatWasExpected) {
  EXPECT_EQ(load_error("battery: {warn_v: 13, critical_v: 14}"),
            "failsafe.yaml:1: battery.critical_v: expected a voltage below warn_v (13.000000 V), "
            "got '14'");
  EXPECT_NE(load_error("battery: {warn_v: 14}").find("battery.critical_v: missing required key"),
            std::string::npos);
  EXPECT_NE(load_error("leak: {action: float}").find("leak.action"), std::string::npos);
  EXPECT_NE(load_error("geofence: {polygon: [[0, 0], [1, 1]]}")
                .find("geofence.polygon: expected a list of 3 to 256"),
            std::string::npos);
  EXPECT_NE(load_error("geofence: {polygon: [[0, 0], [1, 1], [2, 2]]}").find("an area"),
            std::string::npos);
  EXPECT_NE(load_error("gnss: {lost_after_s: 5, use_fix: false}").find("gnss.use_odometry"),
            std::string::npos);
  EXPECT_NE(load_error("batery: {}").find("batery: unknown key"), std::string::npos);
  EXPECT_NE(load_error("depth_limit: {limit_m: -1}").find("depth_limit.limit_m"),
            std::string::npos);
}

}  // namespace
}  // namespace tiller::failsafe
