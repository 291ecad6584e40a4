// tiller-nav: the EKF's predict and update against hand-computed values, and the node on
// synthetic sensor streams (test/nav/synthetic.hpp): convergence on a straight line and in
// turns with a 2.5 m CEP GNSS at 5 Hz and a consumer IMU, an outlier refused and counted, a 20 s
// GNSS outage bridged by dead reckoning, invalid past the limit, an ROV without GNSS, replay
// identity, config errors; the sway constraint by hand, its gate, the current it estimates in a
// synthetic current, and nothing changed with it off.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "core/angles.hpp"
#include "core/config.hpp"
#include "nav/ekf.hpp"
#include "nav/nav_node.hpp"
#include "nav/nav_params.hpp"
#include "runtime/channels.hpp"
#include "synthetic.hpp"

namespace tiller::nav {
namespace {

using test::Leg;
using test::Synthetic;

// ---- the filter, by hand

Ekf hand_filter(double p_diag) {
  Ekf f(ProcessNoise{0.01, 0.02, 0.01, 1e-4, 1e-8});
  State x = State::Zero();
  x(kU) = 1.0;
  f.reset(x, Covariance::Identity() * p_diag);
  return f;
}

TEST(NavEkf, PredictMovesAlongTheHeadingAndGrowsTheCovariance) {
  Ekf f = hand_filter(1.0);
  Motion m;
  m.r = 0.2;
  f.predict(0.1, m);
  EXPECT_NEAR(f.x()(kN), 0.1, 1e-12);  // u dt along psi = 0
  EXPECT_NEAR(f.x()(kE), 0.0, 1e-12);
  EXPECT_NEAR(f.x()(kPsi), 0.02, 1e-12);  // r dt
  // F rows: n = [1 0 0 dt 0 0 0 0]; e = [0 1 0 0 dt 0 u dt 0]; psi = [.. 1 -dt]; P = I.
  EXPECT_NEAR(f.P()(kN, kN), 1 + 0.01 + 0.01 * 0.1, 1e-12);
  EXPECT_NEAR(f.P()(kE, kE), 1 + 0.01 + 0.01 + 0.01 * 0.1, 1e-12);
  EXPECT_NEAR(f.P()(kE, kPsi), 0.1, 1e-12);
  EXPECT_NEAR(f.P()(kPsi, kPsi), 1 + 0.01 + 1e-4 * 0.1, 1e-12);
  EXPECT_NEAR(f.P()(kPsi, kBiasR), -0.1, 1e-12);
  EXPECT_NEAR(f.P()(kU, kU), 1 + 0.02 * 0.1, 1e-12);
  // Heading pi/2: the same step goes east.
  Ekf g = hand_filter(1.0);
  g.set_heading(kPi / 2, 1.0);
  g.predict(0.5, Motion{});
  EXPECT_NEAR(g.x()(kE), 0.5, 1e-12);
  EXPECT_NEAR(g.x()(kN), 0.0, 1e-12);
}

TEST(NavEkf, AccelerationDrivesTheBodyVelocity) {
  // u = 1, forward acceleration 0.5, yaw rate 0.2: u' = a_x + r v = 0.5, v' = a_y - r u = -0.2.
  Ekf f = hand_filter(1.0);
  Motion m;
  m.accel = true;
  m.ax = 0.5;
  m.r = 0.2;
  f.predict(0.1, m);
  EXPECT_NEAR(f.x()(kU), 1.05, 1e-12);
  EXPECT_NEAR(f.x()(kV), -0.02, 1e-12);
  EXPECT_NEAR(f.P()(kU, kBiasAx), -0.1, 1e-12);  // F(u, b_ax) = -dt; P = I
  EXPECT_NEAR(f.P()(kV, kBiasR), 0.1, 1e-12);    // F(v, b_r) = u dt
  // A steady turn: the accelerometer reads the centripetal r u starboard; u and v stay.
  Ekf g = hand_filter(1.0);
  Motion turn;
  turn.accel = true;
  turn.r = 0.2;
  turn.ay = 0.2 * 1.0;
  for (int i = 0; i < 10; ++i) g.predict(0.02, turn);
  EXPECT_NEAR(g.x()(kU), 1.0, 1e-12);
  EXPECT_NEAR(g.x()(kV), 0.0, 1e-12);
  // Without `accel` the velocity is a random walk: the acceleration is not used.
  Ekf h = hand_filter(1.0);
  m.accel = false;
  h.predict(0.1, m);
  EXPECT_NEAR(h.x()(kU), 1.0, 1e-12);
}

TEST(NavEkf, ScalarAndPlanarUpdatesMatchTheKalmanGain) {
  Ekf f = hand_filter(4.0);
  // Depth: P = 4, R = 1, z = 1: K = 0.8, x = 0.8, P = 0.8, NIS = 1 / 5.
  const UpdateResult r = f.update_depth(1.0, 1.0, 10.8);
  EXPECT_TRUE(r.accepted);
  EXPECT_NEAR(r.nis, 0.2, 1e-12);
  EXPECT_NEAR(f.x()(kD), 0.8, 1e-12);
  EXPECT_NEAR(f.P()(kD, kD), 0.8, 1e-12);
  // North-east: P = 3 I, R = I, z = (2, -2): K = 0.75, x = (1.5, -1.5), P = 0.75, NIS = 8 / 4.
  Ekf g = hand_filter(3.0);
  const UpdateResult q =
      g.update_position_ne(Eigen::Vector2d(2, -2), Eigen::Matrix2d::Identity(), 13.8);
  EXPECT_NEAR(q.nis, 2.0, 1e-12);
  EXPECT_NEAR(g.x()(kN), 1.5, 1e-12);
  EXPECT_NEAR(g.x()(kE), -1.5, 1e-12);
  EXPECT_NEAR(g.P()(kN, kN), 0.75, 1e-12);
  EXPECT_NEAR(g.P()(kU, kU), 3.0, 1e-12);  // uncorrelated: untouched
}

TEST(NavEkf, GateRefusesAnOutlierAndLeavesTheState) {
  Ekf f = hand_filter(4.0);
  // z = 10, S = 5: NIS = 20 > 10.8.
  const UpdateResult r = f.update_depth(10.0, 1.0, 10.8);
  EXPECT_FALSE(r.accepted);
  EXPECT_NEAR(r.nis, 20.0, 1e-12);
  EXPECT_EQ(f.x()(kD), 0.0);
  EXPECT_EQ(f.P()(kD, kD), 4.0);
  EXPECT_TRUE(f.update_depth(10.0, 1.0, 0.0).accepted);  // gate 0: no gate
}

TEST(NavEkf, SwayUpdateMatchesTheHandComputedGain) {
  Ekf f = hand_filter(1.0);  // P = I, u = 1
  f.set_heading(kPi / 2, 1.0);
  f.set_state(kV, 0.05, 1.0);
  f.set_state(kCurrentN, 0.2, 1.0);
  f.set_state(kCurrentE, 0.1, 1.0);
  Motion m;
  m.r = 0.2;
  // Heading east: the current's starboard component v_c = -sin(psi) c_n + cos(psi) c_e = -0.2,
  // y = v_c - v = -0.25. H: v 1, psi cos(psi) c_n + sin(psi) c_e = 0.1, c_n sin(psi) = 1, c_e
  // -cos(psi) = 0. R = (0.02 + 0.5 |0.2| |1|)^2 = 0.0144; S = 1 + 0.01 + 1 + 0.0144 = 2.0244.
  EXPECT_NEAR(Ekf::sway_std(0.02, 0.5, -0.2, 1.0), 0.12, 1e-15);
  const double s = 2.0244, y = -0.25;
  const UpdateResult r = f.update_sway(m, 0.02, 0.5, 10.8);
  EXPECT_TRUE(r.accepted);
  EXPECT_NEAR(r.nis, y * y / s, 1e-12);
  // P = I: K = H^T / S, each state moved by H_i y / S.
  EXPECT_NEAR(f.x()(kV), 0.05 + y / s, 1e-12);
  EXPECT_NEAR(f.x()(kPsi), kPi / 2 + 0.1 * y / s, 1e-12);
  EXPECT_NEAR(f.x()(kCurrentN), 0.2 + y / s, 1e-12);
  EXPECT_NEAR(f.x()(kCurrentE), 0.1, 1e-12);
  EXPECT_NEAR(f.x()(kU), 1.0, 1e-12);
  // P = I - H^T H / S (Joseph form, the same for the optimal gain).
  EXPECT_NEAR(f.P()(kV, kV), 1 - 1 / s, 1e-12);
  EXPECT_NEAR(f.P()(kV, kCurrentN), -1 / s, 1e-12);
  EXPECT_NEAR(f.P()(kPsi, kCurrentN), -0.1 / s, 1e-12);
  EXPECT_NEAR(f.P()(kCurrentE, kCurrentE), 1.0, 1e-12);
  // The bias counts in the rate: r - b_r = 0 leaves the straight's 1-sigma only.
  Ekf g = hand_filter(1.0);
  g.set_state(kBiasR, 0.2, 1e-6);
  g.set_state(kV, 0.5, 1.0);
  const UpdateResult q = g.update_sway(m, 0.02, 0.5, 0);
  EXPECT_NEAR(q.nis, 0.25 / 2.0004, 1e-12);  // psi 0, c 0: S = P_vv + P_cece + 0.02^2
}

TEST(NavEkf, SwayGateRefusesOneMetrePerSecondSideways) {
  Ekf f = hand_filter(1e-3);
  f.set_state(kV, 1.0, 1e-3);  // v = 1 m/s, the current 0: y = -1
  Motion m;
  const State before = f.x();
  const Covariance p_before = f.P();
  // S = 1e-3 (v) + 1e-3 (c_e, psi 0) + 0.02^2: NIS = 1 / 0.0024 = 417 > 10.8.
  const UpdateResult r = f.update_sway(m, 0.02, 0.5, 10.8);
  EXPECT_FALSE(r.accepted);
  EXPECT_NEAR(r.nis, 1 / 0.0024, 1e-9);
  EXPECT_EQ(f.x(), before);
  EXPECT_EQ(f.P(), p_before);
}

TEST(NavEkf, HeadingInnovationWrapsAcrossPi) {
  Ekf f = hand_filter(1.0);
  f.set_heading(3.0, 1.0);
  // z = -3.1 is 2 pi - 6.1 = 0.1832 ahead of 3.0, not 6.1 behind: psi = 3.0 + 0.0916.
  f.update_heading(-3.1, 1.0, 10.8);
  EXPECT_NEAR(f.x()(kPsi), 3.0 + 0.5 * (2 * kPi - 6.1), 1e-12);
}

TEST(NavEkf, VelocityMeasurementIsTheBodyVelocityRotated) {
  Ekf f = hand_filter(1.0);
  f.set_heading(kPi / 2, 1e-6);
  f.set_velocity_body(0.0, 0.0, 1.0);
  // Heading east: (vn, ve) = (0, 2) is u = 2.
  f.update_velocity_ne(Eigen::Vector2d(0, 2), Eigen::Matrix2d::Identity() * 1e-6, Motion{}, 0);
  EXPECT_NEAR(f.x()(kU), 2.0, 1e-5);
  EXPECT_NEAR(f.x()(kV), 0.0, 1e-5);
}

// ---- the node on synthetic streams

struct NullBus : Bus {
  void publish(std::string_view, const std::uint8_t*, int) override {}
};

NavParams usv_params() {
  NavParams p = load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/usv.yaml");
  p.fixed_datum = true;  // the truth's origin, so errors compare directly
  p.datum_latitude_deg = test::kLat0;
  p.datum_longitude_deg = test::kLon0;
  return p;
}

struct Stats {
  double pos_sq = 0, head_sq = 0, max_pos = 0;
  int n = 0;
  double pos_rms() const { return std::sqrt(pos_sq / n); }
  double head_rms_deg() const { return rad_to_deg(std::sqrt(head_sq / n)); }
};

// What the run feeds: return false from `gnss_on` to drop the fix at t; `at_tick` sees each
// published odometry with the truth.
struct Feed {
  std::function<bool(TimeUs)> gnss_on = [](TimeUs) { return true; };
  std::function<void(TimeUs, gnss_fix_t&)> edit_fix = [](TimeUs, gnss_fix_t&) {};
  std::function<void(TimeUs, const odometry_t&, const test::Truth&)> at_tick =
      [](TimeUs, const odometry_t&, const test::Truth&) {};
  bool pressure = false;
  bool gnss = true;
  bool dvl = false;  // at 10 Hz while dvl_on says so
  std::function<bool(TimeUs)> dvl_on = [](TimeUs) { return true; };
  std::function<void(TimeUs, dvl_t&)> edit_dvl = [](TimeUs, dvl_t&) {};
  int copies = 1;  // each fix delivered this many times (a driver that repeats an epoch)
};

// IMU at 100 Hz, heading at 10 Hz, GNSS at 5 Hz, pressure at 20 Hz; errors from `from_s` on.
Stats fly(NavNode& node, Synthetic& syn, double from_s, const Feed& f = {}) {
  NullBus bus;
  node.attach(&bus);
  Stats s;
  const TimeUs end = from_seconds(syn.duration_s());
  for (TimeUs t = 0; t <= end; t += 10'000) {
    syn.advance_to(t);
    if (t % node.tick_period() == 0) {
      node.tick(t);
      const odometry_t& o = node.last_odometry();
      const test::Truth& tr = syn.truth();
      f.at_tick(t, o, tr);
      if (to_seconds(t) >= from_s) {
        const double dp = std::hypot(o.position[0] - tr.n, o.position[1] - tr.e);
        const double dh = angle_diff(o.orientation[2], tr.psi);
        s.pos_sq += dp * dp;
        s.head_sq += dh * dh;
        s.max_pos = std::max(s.max_pos, dp);
        ++s.n;
      }
    }
    node.on_imu(syn.imu(t), t);
    if (t % 100'000 == 0) node.on_heading(syn.heading(t), t);
    if (f.pressure && t % 50'000 == 0) node.on_pressure(syn.pressure(t), t);
    if (f.dvl && t % 100'000 == 0 && f.dvl_on(t)) {
      dvl_t m = syn.dvl(t);
      f.edit_dvl(t, m);
      node.on_dvl(m, t);
    }
    if (f.gnss && t % 200'000 == 0 && f.gnss_on(t)) {
      gnss_fix_t m = syn.gnss(t);
      f.edit_fix(t, m);
      for (int c = 0; c < f.copies; ++c) node.on_gnss(m, t);
    }
  }
  return s;
}

TEST(NavNode, ConvergesOnAStraightLine) {
  NavNode node(usv_params());
  Synthetic syn({{180, 0.0}}, 7);
  const Stats s = fly(node, syn, 20);
  std::printf("straight: position RMS %.3f m (max %.3f), heading RMS %.3f deg\n", s.pos_rms(),
              s.max_pos, s.head_rms_deg());
  std::printf("gated: %lld fixes, %lld velocities, %lld headings of %lld fixes used\n",
              static_cast<long long>(node.counter_value("rejected.gnss.gate")),
              static_cast<long long>(node.counter_value("rejected.gnss_velocity.gate")),
              static_cast<long long>(node.counter_value("rejected.heading.gate")),
              static_cast<long long>(node.counter_value("gnss.fixes_used")));
  EXPECT_LE(s.pos_rms(), 0.5);
  EXPECT_LE(s.head_rms_deg(), 1.0);
  EXPECT_EQ(node.last_odometry().valid, odometry_t::VALID_ALL);
  EXPECT_EQ(node.rejected(), node.counter_value("rejected.gnss.gate") +
                                 node.counter_value("rejected.gnss_velocity.gate") +
                                 node.counter_value("rejected.heading.gate"));
}

// Issue 31: the RTK state is used as accuracy when the receiver gives no statistics of its own,
// and an unknown accuracy is poor (default_std_m), not perfect. The same flight's fixes, with
// gpsd's DOP model saying 3 m: the filter's position 1-sigma at the end follows the fix type.
TEST(NavNode, TheRtkStateIsTheAccuracyWhenTheReceiverGivesNone) {
  auto final_sigma = [](std::int8_t fix, std::int8_t source, double std_m) {
    NavParams p = usv_params();
    NavNode node(p);
    test::Noise rtk_receiver;  // positions as good as an RTK fix: the gate refuses none
    rtk_receiver.gnss_std_m = 0.02;
    Synthetic syn({{60, 0.0}}, 7, rtk_receiver);
    Feed f;
    f.edit_fix = [&](TimeUs, gnss_fix_t& m) {
      m.fix_type = fix;
      m.accuracy_source = source;
      m.position_std[0] = m.position_std[1] = std_m;
    };
    fly(node, syn, 20, f);
    return std::sqrt(node.last_odometry().pose_covariance[0]);
  };
  using G = gnss_fix_t;
  const double dop = final_sigma(G::FIX_3D, G::ACCURACY_DOP, 3.0);
  const double fixed = final_sigma(G::FIX_RTK_FIXED, G::ACCURACY_DOP, 3.0);
  const double flt = final_sigma(G::FIX_RTK_FLOAT, G::ACCURACY_DOP, 3.0);
  const double own = final_sigma(G::FIX_RTK_FIXED, G::ACCURACY_RECEIVER, 3.0);
  const double none = final_sigma(G::FIX_3D, G::ACCURACY_NONE, 0.0);
  const double fixed_none = final_sigma(G::FIX_RTK_FIXED, G::ACCURACY_NONE, 0.0);
  std::printf(
      "position 1-sigma at the end: 3D+DOP 3 m %.3f, RTK fixed %.3f, RTK float %.3f, "
      "RTK fixed with the receiver's own 3 m %.3f, unknown %.3f, RTK fixed unknown %.3f\n",
      dop, fixed, flt, own, none, fixed_none);
  EXPECT_LT(fixed, flt);       // fixed: min(3, 0.05) floored to min_std_m 0.3
  EXPECT_LT(flt, dop);         // float: min(3, 0.5)
  EXPECT_DOUBLE_EQ(own, dop);  // the receiver's own statistics win over the state
  EXPECT_GT(none, fixed);      // unknown: default_std_m 2.5, not 0
  EXPECT_LT(none, dop);
  EXPECT_DOUBLE_EQ(fixed_none, fixed);  // unknown but RTK fixed: the state's 1-sigma
}

TEST(NavNode, ConvergesInTurns) {
  NavNode node(usv_params());
  // 20 s straight, 60 s turning right at 0.1 rad/s, 20 s straight, 40 s left at 0.15 rad/s.
  Synthetic syn({{20, 0.0}, {60, 0.1}, {20, 0.0}, {40, -0.15}, {20, 0.0}}, 11);
  const Stats s = fly(node, syn, 20);
  std::printf("turns: position RMS %.3f m (max %.3f), heading RMS %.3f deg\n", s.pos_rms(),
              s.max_pos, s.head_rms_deg());
  EXPECT_LE(s.pos_rms(), 0.5);
  EXPECT_LE(s.head_rms_deg(), 1.0);
}

TEST(NavNode, RefusesAndCountsAnOutlierFix) {
  // The same seeded run twice, the second with one fix 40 m north at 60 s: exactly one more
  // refusal (a 1-in-1000 gate also refuses a few honest fixes in both runs).
  NavNode ref(usv_params()), node(usv_params());
  Synthetic sr({{90, 0.0}}, 3), syn({{90, 0.0}}, 3);
  fly(ref, sr, 20);
  Feed f;
  f.edit_fix = [](TimeUs t, gnss_fix_t& m) {
    if (t == 60'000'000) m.latitude += 40.0 / 111'000;
  };
  double worst_after = 0;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth& tr) {
    if (t > 60'000'000 && t < 65'000'000)
      worst_after = std::max(worst_after, std::hypot(o.position[0] - tr.n, o.position[1] - tr.e));
  };
  fly(node, syn, 20, f);
  EXPECT_EQ(node.counter_value("rejected.gnss.gate"), ref.counter_value("rejected.gnss.gate") + 1);
  EXPECT_EQ(node.rejected(), ref.rejected() + 1);
  EXPECT_LT(worst_after, 1.5);
}

// One measurement is fused once: the same epoch again (the same gnss_utime; gpsd repeats a TPV
// while it learns a receiver's cycle) is refused and counted, so a run with every fix delivered
// twice publishes exactly the odometry of the run with each fix once. Before the check the
// doubled run's position variance was about half the single run's.
TEST(NavNode, AFixOfTheSameEpochTwiceIsFusedOnce) {
  NavNode once(usv_params()), twice(usv_params());
  Synthetic s1({{60, 0.05}}, 5), s2({{60, 0.05}}, 5);
  std::vector<odometry_t> a, b;
  Feed f;
  f.edit_fix = [](TimeUs t, gnss_fix_t& m) { m.gnss_utime = 1'796'000'000'000'000 + t; };
  f.at_tick = [&](TimeUs, const odometry_t& o, const test::Truth&) { a.push_back(o); };
  fly(once, s1, 20, f);
  f.copies = 2;
  f.at_tick = [&](TimeUs, const odometry_t& o, const test::Truth&) { b.push_back(o); };
  fly(twice, s2, 20, f);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].position[0], b[i].position[0]) << "tick " << i;
    ASSERT_EQ(a[i].position[1], b[i].position[1]) << "tick " << i;
    ASSERT_EQ(a[i].pose_covariance, b[i].pose_covariance) << "tick " << i;
  }
  const auto fixes = once.counter_value("gnss.fixes_used");
  EXPECT_GT(fixes, 250);  // 5 Hz for 60 s, less a few gated
  EXPECT_EQ(twice.counter_value("gnss.fixes_used"), fixes);
  EXPECT_EQ(twice.counter_value("rejected.gnss.repeated"),
            fixes + once.counter_value("rejected.gnss.gate"));
  EXPECT_EQ(once.counter_value("rejected.gnss.repeated"), 0);
}

TEST(NavNode, BridgesAGnssOutageByDeadReckoning) {
  NavNode node(usv_params());
  Synthetic syn({{40, 0.0}, {30, 0.05}, {50, 0.0}}, 5);
  Feed f;
  f.gnss_on = [](TimeUs t) { return t < 60'000'000 || t >= 80'000'000; };
  double var_start = 0, var_end = 0, err_end = 0, err_recovered = 0;
  TimeUs dr_from = -1, dr_to = -1;
  bool valid_throughout = true;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth& tr) {
    const bool dr = o.valid & odometry_t::DEAD_RECKONING;
    if (dr && dr_from < 0) dr_from = t;
    if (!dr && dr_from >= 0 && dr_to < 0) dr_to = t;
    if (t == 61'000'000) var_start = o.pose_covariance[0];
    if (t == 79'980'000) {
      var_end = o.pose_covariance[0];
      err_end = std::hypot(o.position[0] - tr.n, o.position[1] - tr.e);
    }
    if (t == 90'000'000) err_recovered = std::hypot(o.position[0] - tr.n, o.position[1] - tr.e);
    if (t > 20'000'000 && !(o.valid & odometry_t::VALID_POSITION)) valid_throughout = false;
  };
  fly(node, syn, 20, f);
  std::printf(
      "outage: DR from %.2f to %.2f s, north var %.3f -> %.3f m^2, error at end %.2f m, "
      "10 s after %.2f m\n",
      to_seconds(dr_from), to_seconds(dr_to), var_start, var_end, err_end, err_recovered);
  EXPECT_GE(dr_from, 60'800'000);  // the last fix at 59.8 s, timeout 1 s
  EXPECT_LE(dr_from, 60'900'000);
  EXPECT_GE(dr_to, 80'000'000);
  EXPECT_LE(dr_to, 80'020'000);  // the first fix back
  EXPECT_GT(var_end, 10 * var_start);
  EXPECT_LT(err_end, 5.0);
  EXPECT_LT(err_recovered, 1.0);
  EXPECT_TRUE(valid_throughout);  // 1-sigma stays under the 10 m limit over 20 s
  EXPECT_EQ(node.counter_value("dead_reckoning.entered"), 1);
}

TEST(NavNode, PositionInvalidPastTheLimitThenBack) {
  NavParams p = usv_params();
  p.limits.position_std_m = 2.0;
  NavNode node(p);
  Synthetic syn({{120, 0.0}}, 9);
  Feed f;
  f.gnss_on = [](TimeUs t) { return t < 40'000'000 || t >= 90'000'000; };
  TimeUs invalid_at = -1, valid_again = -1;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth&) {
    const bool pos = o.valid & odometry_t::VALID_POSITION;
    if (t > 40'000'000 && !pos && invalid_at < 0) invalid_at = t;
    if (invalid_at >= 0 && pos && valid_again < 0) valid_again = t;
    if (t > 40'000'000 && !pos) {
      EXPECT_GT(std::sqrt(o.pose_covariance[0]), 1.0);
    }
  };
  fly(node, syn, 20, f);
  std::printf("limit 2 m: invalid %.2f s into the outage, valid again %.2f s after it\n",
              to_seconds(invalid_at - 40'000'000), to_seconds(valid_again - 90'000'000));
  EXPECT_GT(invalid_at, 40'000'000);
  EXPECT_LT(invalid_at, 90'000'000);
  EXPECT_GE(valid_again, 90'000'000);
  EXPECT_LT(valid_again, 91'000'000);
}

TEST(NavNode, RovWithoutGnssHasDepthAndAttitudeButNoPosition) {
  NavNode node(load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/rov.yaml"));
  Synthetic syn({{30, 0.0}, {30, 0.1}}, 2);
  syn.mutable_truth().d = 12.0;
  syn.mutable_truth().u = 0.3;
  Feed f;
  f.pressure = true;
  f.gnss = false;
  double depth_err = 0, head_sq = 0;
  int n = 0;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth& tr) {
    if (t < 5'000'000) return;
    EXPECT_EQ(o.valid, int{odometry_t::VALID_ATTITUDE} | int{odometry_t::VALID_DEPTH}) << t;
    depth_err = std::max(depth_err, std::abs(o.position[2] - tr.d));
    head_sq += std::pow(angle_diff(o.orientation[2], tr.psi), 2);
    ++n;
  };
  fly(node, syn, 5, f);
  EXPECT_LT(depth_err, 0.06);  // the largest over the run; the sensor's 1-sigma is 0.02 m
  EXPECT_LT(rad_to_deg(std::sqrt(head_sq / n)), 1.0);
  EXPECT_NE(node.counter_value("odometry.position_invalid"), 0);
  EXPECT_EQ(node.rejected(), node.counter_value("rejected.heading.gate") +
                                 node.counter_value("rejected.depth.gate"));
}

NavParams rov_dvl_params() {
  return load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/rov_dvl.yaml");
}

TEST(NavEkf, DvlVelocityUpdateByHand) {
  // P = I on u v w, R = I: K = 1/2 on each, so the state goes half way and the variance halves.
  Ekf f = hand_filter(1.0);
  const UpdateResult r =
      f.update_velocity_body(Eigen::Vector3d(2.0, 0.4, -0.2), Eigen::Matrix3d::Identity(), 0.0);
  EXPECT_TRUE(r.accepted);
  EXPECT_NEAR(r.nis, (1.0 + 0.16 + 0.04) / 2, 1e-12);  // y = [1 0.4 -0.2], S = 2 I
  EXPECT_NEAR(f.x()(kU), 1.5, 1e-12);
  EXPECT_NEAR(f.x()(kV), 0.2, 1e-12);
  EXPECT_NEAR(f.x()(kW), -0.1, 1e-12);
  EXPECT_NEAR(f.P()(kU, kU), 0.5, 1e-12);
  EXPECT_NEAR(f.P()(kN, kN), 1.0, 1e-12);  // uncorrelated: untouched
  Ekf g = hand_filter(1.0);
  EXPECT_FALSE(g.update_velocity_body(Eigen::Vector3d(10, 0, 0), Eigen::Matrix3d::Identity(),
                                      16.3)
                   .accepted);  // NIS 40.5 over the gate
  EXPECT_EQ(g.x()(kU), 1.0);
}

TEST(NavNode, RovDeadReckonsOnTheDvl) {
  NavNode node(rov_dvl_params());
  Synthetic syn({{10, 0.0}, {20, 0.1}, {30, 0.0}}, 3);
  syn.mutable_truth().d = 12.0;
  syn.mutable_truth().u = 0.3;
  syn.mutable_truth().psi = kPi / 2;  // east
  Feed f;
  f.pressure = true;
  f.gnss = false;
  f.dvl = true;
  double max_err = 0, last_var = 0, var_5s = 0;
  bool grows = true;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth& tr) {
    if (t < 1'000'000) return;
    EXPECT_EQ(o.valid, int{odometry_t::VALID_ALL} | int{odometry_t::DEAD_RECKONING}) << t;
    max_err = std::max(max_err, std::hypot(o.position[0] - tr.n, o.position[1] - tr.e));
    last_var = o.pose_covariance[0] + o.pose_covariance[7];
    // Sampled every 5 s (a velocity update may take a little off through the correlation).
    if (t % 5'000'000 == 0) {
      grows = grows && last_var > var_5s;
      var_5s = last_var;
    }
  };
  fly(node, syn, 1, f);
  const double std_m = std::sqrt(last_var / 2);
  std::printf(
      "DVL dead reckoning, 60 s at 0.3 m/s with a turn: largest error %.3f m, final "
      "1-sigma %.3f m\n",
      max_err, std_m);
  // 18 m flown; the velocity's noise integrates to a few cm, the heading's (2 deg, filtered)
  // error turns the track by a fraction of a degree.
  EXPECT_LT(max_err, 0.3);
  EXPECT_TRUE(grows);  // dead reckoning: the position's uncertainty only grows
  EXPECT_GT(std_m, 0.01);
  EXPECT_LT(std_m, 1.0);
  EXPECT_GT(node.counter_value("dvl.used"), 590);
  EXPECT_EQ(node.counter_value("dvl.lost"), 0);
  EXPECT_NE(node.dvl_status().find("dead reckoning on the DVL: position 1-sigma"),
            std::string::npos)
      << node.dvl_status();
}

TEST(NavNode, DvlLossMakesPositionAndVelocityInvalidUntilItIsBack) {
  NavNode node(rov_dvl_params());
  Synthetic syn({{40, 0.0}}, 5);
  syn.mutable_truth().d = 5.0;
  syn.mutable_truth().u = 0.2;
  Feed f;
  f.pressure = true;
  f.gnss = false;
  f.dvl = true;
  f.dvl_on = [](TimeUs t) { return t < 10'000'000 || t >= 20'000'000; };  // 10 s dropout
  TimeUs invalid_at = -1, valid_again = -1;
  double jump = 0, before_n = 0;
  std::string lost_status;
  f.at_tick = [&](TimeUs t, const odometry_t& o, const test::Truth&) {
    const bool pos = o.valid & odometry_t::VALID_POSITION;
    const bool vel = o.valid & odometry_t::VALID_VELOCITY;
    EXPECT_EQ(pos, vel) << t;
    if (t > 1'000'000) {
      EXPECT_TRUE(o.valid & odometry_t::VALID_DEPTH) << t;
    }
    if (t > 10'000'000 && !pos && invalid_at < 0) invalid_at = t;
    if (t > 20'000'000 && pos && valid_again < 0) {
      valid_again = t;
      jump = std::abs(o.position[0] - before_n);
    }
    if (t == 15'000'000) lost_status = node.dvl_status();
    before_n = o.position[0];
  };
  fly(node, syn, 0, f);
  // timeout_s 0.6 past the last report at 9.9 s.
  EXPECT_GE(invalid_at, 10'400'000);
  EXPECT_LE(invalid_at, 10'600'000);
  EXPECT_GE(valid_again, 20'000'000);
  EXPECT_LE(valid_again, 20'100'000);
  // The position carries on: a tick's travel (4 mm) and the velocity restarting, no step (an
  // update instead of the restart moved it 62 mm).
  EXPECT_LT(jump, 0.02);
  EXPECT_EQ(node.counter_value("dvl.lost"), 1);
  EXPECT_NE(lost_status.find("DVL lost: no velocity used for"), std::string::npos) << lost_status;
}

TEST(NavNode, DvlWithoutLockOrWithAPoorFomIsNotUsed) {
  NavNode node(rov_dvl_params());
  Synthetic syn({{5, 0.0}}, 6);
  Feed f;
  f.pressure = true;
  f.gnss = false;
  f.dvl = true;
  f.edit_dvl = [](TimeUs t, dvl_t& m) {
    if (t % 300'000 == 0) {  // every third: no lock
      m.bottom_lock = false;
      m.velocity[0] = m.velocity[1] = m.velocity[2] = 0;
      m.altitude = -1;
    } else if (t % 300'000 == 100'000) {
      m.fom = 0.2;  // over max_fom_mps 0.05
    }
  };
  fly(node, syn, 0, f);
  EXPECT_EQ(node.counter_value("dvl.no_lock"), 17);       // t = 0, 0.3, ..., 4.8 s
  EXPECT_EQ(node.counter_value("rejected.dvl.fom"), 17);  // 0.1 .. 4.9 s
  EXPECT_EQ(node.counter_value("dvl.used"), 17);
  // A lever arm: the DVL 0.2 m forward sees omega x r = (0, 0.1, 0) at r = 0.5 rad/s.
  NavParams p = rov_dvl_params();
  p.dvl.lever_arm_m[0] = 0.2;
  p.dvl.lever_arm_m[2] = 0;
  NavNode turning(p);
  Synthetic spin({{20, 0.5}}, 7);
  spin.mutable_truth().u = 0.0;
  Feed g;
  g.pressure = true;
  g.gnss = false;
  g.dvl = true;
  g.edit_dvl = [](TimeUs, dvl_t& m) { m.velocity[1] += 0.2 * 0.5; };
  fly(turning, spin, 0, g);
  EXPECT_NEAR(turning.last_odometry().velocity[1], 0.0, 0.01);
}

// A depth the pressure gate keeps refusing is reset to the sensor after depth.reset_after samples
// (found in rov_dvl_live_test: an estimate that had run away was never corrected again).
TEST(NavNode, DepthRefusedInARowIsResetToThePressure) {
  NavNode node(rov_dvl_params());
  NullBus bus;
  node.attach(&bus);
  Synthetic syn({{6, 0.0}}, 8);
  syn.mutable_truth().d = 2.0;
  for (TimeUs t = 0; t <= 6'000'000; t += 50'000) {
    if (t % node.tick_period() == 0) node.tick(t);
    pressure_t m = syn.pressure(t);
    if (t >= 2'000'000) {  // the sensor now reads 5 m deeper: far outside the gate
      m.depth += 5.0;
      m.pressure = m.surface_pressure + m.depth * m.water_density * 9.80665;
    }
    node.on_pressure(m, t);
  }
  EXPECT_EQ(node.counter_value("rejected.depth.gate"), 25);
  EXPECT_NEAR(node.filter().x()(kD), 7.0, 0.1);
  EXPECT_EQ(node.counter_value("resets"), 1);
}

TEST(NavNode, FirstFixIsTheDatumAndRunsReplayIdentically) {
  NavParams p = load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/usv.yaml");
  NavNode a(p), b(p);
  Synthetic sa({{30, 0.05}}, 4), sb({{30, 0.05}}, 4);
  fly(a, sa, 0);
  fly(b, sb, 0);
  EXPECT_TRUE(a.has_datum());
  const odometry_t &oa = a.last_odometry(), &ob = b.last_odometry();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(oa.position[i], ob.position[i]);
  EXPECT_EQ(oa.pose_covariance, ob.pose_covariance);
  // About the first (noisy) fix: within a few sigma of the truth's track, not of its origin.
  EXPECT_LT(std::hypot(oa.position[0] - sa.truth().n, oa.position[1] - sa.truth().e), 8.0);
}

struct DatumBus : Bus {
  std::vector<datum_t> got;
  void publish(std::string_view channel, const std::uint8_t* data, int size) override {
    if (channel != channels::kDatum) return;
    datum_t d{};
    ASSERT_EQ(d.decode(data, 0, size), size);
    got.push_back(d);
  }
};

// TILLER_DATUM: a configured datum at the first tick, then every second, SOURCE_CONFIG; a
// first_fix datum nothing before it is set, then the set point, SOURCE_FIRST_FIX.
TEST(NavNode, PublishesItsDatumOnceItIsSet) {
  NavNode fixed(usv_params());
  DatumBus bus;
  fixed.attach(&bus);
  for (TimeUs t = 0; t <= 2'500'000; t += fixed.tick_period()) fixed.tick(t);
  ASSERT_EQ(bus.got.size(), 3u);  // 0, 1 and 2 s
  EXPECT_EQ(bus.got[0].utime, 0);
  EXPECT_EQ(bus.got[1].utime, 1'000'000);
  EXPECT_EQ(bus.got[0].latitude, test::kLat0);
  EXPECT_EQ(bus.got[0].longitude, test::kLon0);
  EXPECT_EQ(bus.got[0].source, datum_t::SOURCE_CONFIG);

  NavNode first(load_nav_file(std::string(TILLER_SOURCE_DIR) + "/config/nav/usv.yaml"));
  DatumBus bus2;
  first.attach(&bus2);
  Synthetic syn({{30, 0.05}}, 4);
  TimeUs set_at = -1;
  for (TimeUs t = 0; t <= 20'000'000; t += 10'000) {
    syn.advance_to(t);
    if (t % first.tick_period() == 0) {
      const bool had = first.has_datum();
      first.tick(t);
      if (!had) {
        EXPECT_TRUE(bus2.got.empty()) << "a datum published before it was set";
      }
      if (had && set_at < 0) set_at = t;
    }
    first.on_imu(syn.imu(t), t);
    if (t % 100'000 == 0) first.on_heading(syn.heading(t), t);
    if (t % 200'000 == 0) first.on_gnss(syn.gnss(t), t);
  }
  ASSERT_TRUE(first.has_datum());
  ASSERT_FALSE(bus2.got.empty());
  EXPECT_EQ(bus2.got[0].utime, set_at);  // the first tick after the datum was set
  EXPECT_EQ(bus2.got[0].latitude, first.datum_latitude());
  EXPECT_EQ(bus2.got[0].longitude, first.datum_longitude());
  EXPECT_EQ(bus2.got[0].source, datum_t::SOURCE_FIRST_FIX);
  EXPECT_NEAR(bus2.got[0].latitude, test::kLat0, 1e-4);  // within ~10 m of the truth's origin
}

// A boat in a 0.3 m/s current toward the north-east, turning now and then so that both of the
// current's components come across: with the sway constraint the filter's current converges on
// the truth's; without it the current is not observed (it stays 0, uncorrelated).
TEST(NavNode, SwayConstraintEstimatesTheCurrent) {
  const std::vector<Leg> legs = {{30, 0.0}, {30, 0.1}, {40, 0.0}, {30, -0.1},
                                 {40, 0.0}, {30, 0.1}, {60, 0.0}};
  const double cn = 0.3 * std::cos(deg_to_rad(45)), ce = 0.3 * std::sin(deg_to_rad(45));
  NavParams p = usv_params();
  p.sway.enabled = true;
  NavNode on(p), off(usv_params());
  Synthetic son(legs, 5), soff(legs, 5);
  for (Synthetic* s : {&son, &soff}) {
    s->mutable_truth().current_n = cn;
    s->mutable_truth().current_e = ce;
  }
  const Stats a = fly(on, son, 20), b = fly(off, soff, 20);
  const State& x = on.filter().x();
  std::printf(
      "sway constraint: current %.3f, %.3f m/s (truth %.3f, %.3f), 1-sigma %.3f; "
      "position RMS %.3f m, heading %.3f deg (without: %.3f m, %.3f deg); %lld gated\n",
      x(kCurrentN), x(kCurrentE), cn, ce, std::sqrt(on.filter().P()(kCurrentN, kCurrentN)),
      a.pos_rms(), a.head_rms_deg(), b.pos_rms(), b.head_rms_deg(),
      static_cast<long long>(on.counter_value("rejected.sway.gate")));
  EXPECT_NEAR(x(kCurrentN), cn, 0.05);
  EXPECT_NEAR(x(kCurrentE), ce, 0.05);
  EXPECT_LT(on.filter().P()(kCurrentN, kCurrentN), 0.05 * 0.05);
  EXPECT_LE(a.pos_rms(), 0.5);
  EXPECT_LE(a.head_rms_deg(), 1.0);
  EXPECT_LE(on.counter_value("rejected.sway.gate"), 5);
  EXPECT_EQ(off.filter().x()(kCurrentN), 0.0);
  EXPECT_EQ(off.filter().x()(kCurrentE), 0.0);
  EXPECT_TRUE((off.filter().P().topRightCorner<kCoreStates, 2>().isZero(0.0)));
  EXPECT_EQ(off.counter_value("rejected.sway.gate"), 0);
}

// With the constraint off the current states change nothing: other current settings give the
// same odometry bit for bit (the filter's first kCoreStates run as without them).
TEST(NavNode, WithoutTheSwayConstraintTheCurrentChangesNothing) {
  NavParams p = usv_params();
  NavParams q = p;
  q.initial_current_std_mps = 2.0;
  q.process.current = 0.1;
  q.sway.std_mps = 0.5;  // unused while off
  NavNode a(p), b(q);
  const std::vector<Leg> legs = {{20, 0.0}, {20, 0.1}, {20, 0.0}};
  Synthetic sa(legs, 9), sb(legs, 9);
  sa.mutable_truth().current_e = sb.mutable_truth().current_e = 0.3;
  fly(a, sa, 0);
  fly(b, sb, 0);
  const odometry_t &oa = a.last_odometry(), &ob = b.last_odometry();
  for (int i = 0; i < 3; ++i) EXPECT_EQ(oa.position[i], ob.position[i]);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(oa.velocity[i], ob.velocity[i]);
  EXPECT_EQ(oa.pose_covariance, ob.pose_covariance);
  EXPECT_EQ(oa.velocity_covariance, ob.velocity_covariance);
  EXPECT_EQ(a.filter().x().head<kCoreStates>(), b.filter().x().head<kCoreStates>());
}

TEST(NavConfig, ErrorsNameTheKeyAndWhatWasExpected) {
  auto error_of = [](const std::string& text) {
    try {
      load_nav_params(config::Value::parse(text, "nav.yaml"));
    } catch (const config::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("datum: somewhere\n").find("datum: expected first_fix"), std::string::npos)
      << error_of("datum: somewhere\n");
  EXPECT_NE(error_of("datum: first_fix\ngnss: {gate_chi2: -1}\n").find("gnss.gate_chi2"),
            std::string::npos);
  EXPECT_NE(error_of("datum: first_fix\nlimits: {position_std: 3}\n").find("unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("rate_hz: 50\n").find("datum: missing required key"), std::string::npos);
  EXPECT_NE(error_of("datum: {latitude_deg: 91, longitude_deg: 0}\n").find("datum.latitude_deg"),
            std::string::npos);
  EXPECT_NE(error_of("datum: first_fix\nsway: {std_mps: 0}\n").find("sway.std_mps"),
            std::string::npos);
  EXPECT_NE(error_of("datum: first_fix\nsway: {enabled: 3}\n").find("sway.enabled"),
            std::string::npos);
  EXPECT_NE(error_of("datum: first_fix\nsway: {min_speed: 1}\n").find("unknown key"),
            std::string::npos);
  EXPECT_NE(error_of("datum: first_fix\nprocess: {current: -1}\n").find("process.current"),
            std::string::npos);
  // The shipped files: on for the simulated Otter, off on a real one and on an ROV.
  const std::string dir = std::string(TILLER_SOURCE_DIR) + "/config/nav/";
  EXPECT_TRUE(load_nav_file(dir + "usv_sim.yaml").sway.enabled);
  EXPECT_FALSE(load_nav_file(dir + "usv.yaml").sway.enabled);
  EXPECT_FALSE(load_nav_file(dir + "rov.yaml").sway.enabled);
}

}  // namespace
}  // namespace tiller::nav
