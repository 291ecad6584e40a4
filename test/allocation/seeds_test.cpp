// Each preset behaves as its seed says.
//   seed 000: the manual demand reproduces the a/b formulas over a dense stick grid, and the
//             two conditions (direction along J, |F|/|F|max = |J|/|J|max) hold for any layout;
//   seed 001: direction tables; groups scaled independently and only beyond 1 (its text),
//             where its code's indices (Math.max(setpoint[0], setpoint[1]), no abs inside) fail;
//   seed 004: X-drive table with k = 0.6 vs the same hull by geometry; ratio-keeping
//             normalisation; H drive.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "allocation/allocator.hpp"
#include "test_util.hpp"

namespace tiller {
namespace {

using test::preset;
using test::preset_names;

// ------------------------------------------------------------------ seed 000
// The seed's algorithm, from its text. Stick (jx right, jy forward). Pair 2,4 pushes along
// e24 = (1,1)/sqrt2 (forward-right), pair 1,3 along e13 = (-1,1)/sqrt2 (forward-left); thrusters
// 3 and 4 face backwards, so they get the negated pair value. a = |J|/|J|max = max(|jx|,|jy|)
// for the pair nearer to J, b = a*tan(theta_T) for the other, theta_T the angle between J and
// the stronger pair's axis (45 deg - theta_J in the first octant).
std::array<double, 4> seed000_ab(double jx, double jy) {
  const double c24 = (jx + jy) / std::sqrt(2.0), c13 = (-jx + jy) / std::sqrt(2.0);
  if (jx == 0 && jy == 0) return {0, 0, 0, 0};
  const double a = std::max(std::abs(jx), std::abs(jy));
  const bool strong24 = std::abs(c24) >= std::abs(c13);
  const double cs = strong24 ? c24 : c13, cw = strong24 ? c13 : c24;
  const double theta_t = std::atan2(std::abs(cw), std::abs(cs));
  const double b = a * std::tan(theta_t);
  const double vs = std::copysign(a, cs), vw = cw == 0 ? 0.0 : std::copysign(b, cw);
  const double v24 = strong24 ? vs : vw, v13 = strong24 ? vw : vs;
  return {v13, v24, -v13, -v24};  // thrusters 1, 2, 3, 4
}

TEST(Seed000, TextFormulaInTheFirstOctant) {
  // 0 < theta_J < 45: a = jx, b = jx * tan(45 deg - theta_J); jx = 1, jy = 0.5 from the text.
  const auto v = seed000_ab(1.0, 0.5);
  const double theta_j = std::atan2(0.5, 1.0);
  EXPECT_NEAR(v[1], 1.0, 1e-12);                            // pair 2,4 is "a"
  EXPECT_NEAR(-v[0], std::tan(M_PI / 4 - theta_j), 1e-12);  // pair 1,3 is "b"
}

TEST(Seed000, ManualDemandGivesTheSeedsCommandsOverADenseGrid) {
  const Allocator a(preset("seed000_rov4"));
  AllocationResult r;
  double worst = 0;
  const int n = 200;
  for (int ix = -n; ix <= n; ++ix) {
    for (int iy = -n; iy <= n; ++iy) {
      const double jx = ix / double(n), jy = iy / double(n);
      Wrench j = Wrench::Zero();
      j(0) = jy;  // forward -> X
      j(1) = jx;  // right -> Y
      ASSERT_TRUE(a.allocate_manual(j, r));
      const auto want = seed000_ab(jx, jy);
      for (int k = 0; k < 4; ++k)
        worst = std::max(worst, std::abs(r.command[static_cast<std::size_t>(k)] -
                                         want[static_cast<std::size_t>(k)]));
    }
  }
  EXPECT_LT(worst, 1e-12) << "over 401 x 401 stick positions";
}

TEST(Seed000, TwoConditionsHoldForEveryLayout) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const auto& name : preset_names()) {
    const Vehicle v = preset(name);
    if (v.allocation.has_matrix()) continue;  // tables define their own manual mapping
    SCOPED_TRACE(name);
    const Allocator a(v);
    AllocationResult r, edge;
    for (int trial = 0; trial < 300; ++trial) {
      Wrench j = Wrench::Zero();
      for (int ax = 0; ax < 6; ++ax)
        if (!a.unactuated()[static_cast<std::size_t>(ax)]) j(ax) = u(rng) * (trial % 3 ? 1.0 : 0.3);
      for (const auto& axes : a.group_axes()) {
        double m = 0;
        for (int ax : axes) m = std::max(m, std::abs(j(ax)));
        if (m == 0) continue;
        // Single group at a time (other axes 0), so compensation between groups stays out.
        Wrench jg = Wrench::Zero();
        for (int ax : axes) jg(ax) = j(ax);
        ASSERT_TRUE(a.allocate_manual(jg, r));
        ASSERT_TRUE(a.allocate_manual(jg / m, edge));  // the same direction at the square's edge
        Eigen::VectorXd d(axes.size()), got(axes.size()), got_edge(axes.size());
        for (std::size_t k = 0; k < axes.size(); ++k) {
          const int ax = axes[k];
          d(static_cast<Eigen::Index>(k)) = j(ax) * a.axis_max(ax, j(ax) >= 0 ? 1 : -1);
          got(static_cast<Eigen::Index>(k)) = r.achieved(ax);
          got_edge(static_cast<Eigen::Index>(k)) = edge.achieved(ax);
        }
        // Condition 1: along J (each axis weighted by its own maximum).
        const Eigen::VectorXd dn = d.normalized();
        EXPECT_LT((got - got.dot(dn) * dn).norm(), 1e-9 * (1 + got.norm()));
        EXPECT_GT(got.dot(dn), 0);
        // Condition 2: |F| / |F|max = |J| / |J|max = m, with |F|max reached at the edge: some
        // thruster is at its limit there.
        EXPECT_NEAR(got.norm(), m * got_edge.norm(), 1e-9 * (1 + got.norm()));
        bool limit = false;
        for (int i = 0; i < a.size(); ++i)
          limit = limit || edge.saturated[static_cast<std::size_t>(i)];
        EXPECT_TRUE(limit);
        // |F|max is the true largest along that direction (spare thrusters included), computed
        // without the allocator.
        Wrench dw = Wrench::Zero();
        for (std::size_t k = 0; k < axes.size(); ++k) dw(axes[k]) = d(static_cast<Eigen::Index>(k));
        const double best = test::brute_max_scale(v, a.unactuated(), dw);
        EXPECT_NEAR(got_edge.norm(), best * d.norm(), 1e-9 * (1 + got_edge.norm()));
      }
    }
  }
}

TEST(Seed000, StickDirectionIsTheForceDirectionOnTheSymmetricRov) {
  const Allocator a(preset("seed000_rov4"));
  EXPECT_NEAR(a.axis_max(0, 1), a.axis_max(1, 1), 1e-9);
  EXPECT_NEAR(a.axis_max(0, 1), 4 * 30 / std::sqrt(2.0), 1e-9);
  AllocationResult r;
  Wrench j = Wrench::Zero();
  j(0) = 0.5;
  j(1) = 1.0;
  ASSERT_TRUE(a.allocate_manual(j, r));
  EXPECT_NEAR(r.achieved(1) / r.achieved(0), 2.0, 1e-12);
  EXPECT_NEAR(r.achieved(5), 0.0, 1e-9);
}

// ------------------------------------------------------------------ seed 001
// joystick indices as in its code: [0] forward, [1] strafe, [2] pitch, [3] yaw, [5] elevate.
// Thruster order [F, LF, RF, B, LB, RB].
using Joy = std::array<double, 6>;
using Six = std::array<double, 6>;
const Six f_arr = {0, 1, 1, 0, 1, 1}, s_arr = {0, 1, -1, 0, -1, 1}, y_arr = {0, 1, -1, 0, 1, -1},
          e_arr = {1, 0, 0, 1, 0, 0}, p_arr = {1, 0, 0, -1, 0, 0};

Six seed001_setpoint(const Joy& j) {
  Six sp{};
  for (std::size_t i = 0; i < 6; ++i)
    sp[i] = j[0] * f_arr[i] + j[1] * s_arr[i] + j[3] * y_arr[i] + j[5] * e_arr[i] + j[2] * p_arr[i];
  return sp;
}

Six seed001_code(const Joy& j) {  // lines 255-267, as written
  Six sp = seed001_setpoint(j);
  const double max_e = std::abs(std::max(sp[0], sp[1]));
  if (max_e > 1) {
    sp[0] /= max_e;
    sp[3] /= max_e;
  }
  const double max_l = std::abs(std::max({sp[2], sp[3], sp[4], sp[5]}));
  if (max_l > 1) {
    sp[1] /= max_l;
    sp[2] /= max_l;
    sp[4] /= max_l;
    sp[5] /= max_l;
  }
  return sp;
}

Six seed001_text(const Joy& j) {  // the text: F,B and the four vectored scaled apart, |.| > 1
  Six sp = seed001_setpoint(j);
  const double max_v = std::max(std::abs(sp[0]), std::abs(sp[3]));
  if (max_v > 1) {
    sp[0] /= max_v;
    sp[3] /= max_v;
  }
  const double max_h =
      std::max({std::abs(sp[1]), std::abs(sp[2]), std::abs(sp[4]), std::abs(sp[5])});
  if (max_h > 1)
    for (std::size_t i : {1u, 2u, 4u, 5u}) sp[i] /= max_h;
  return sp;
}

// The seed's tables as a vehicle file: config/vehicles/seed001_rov6_table.yaml (duty cycles,
// groups vertical / horizontal, normalise only above 1).
Vehicle seed001_table_vehicle() {
  return preset("seed001_rov6_table");
}

TEST(Seed001, TheTableFileHoldsTheSeedsArrays) {
  const Vehicle v = seed001_table_vehicle();
  ASSERT_EQ(v.allocation.matrix_axes, (std::vector<int>{0, 1, 2, 4, 5}));  // X Y Z M N
  const char* order[6] = {"F", "LF", "RF", "B", "LB", "RB"};
  for (std::size_t i = 0; i < 6; ++i) {
    const int r = v.index_of(order[i]);
    ASSERT_GE(r, 0);
    EXPECT_EQ(v.allocation.matrix(r, 0), f_arr[i]);
    EXPECT_EQ(v.allocation.matrix(r, 1), s_arr[i]);
    EXPECT_EQ(v.allocation.matrix(r, 2), -e_arr[i]);  // FRD: elevation up is -Z
    EXPECT_EQ(v.allocation.matrix(r, 3), p_arr[i]);
    EXPECT_EQ(v.allocation.matrix(r, 4), y_arr[i]);
  }
  EXPECT_TRUE(v.allocation.matrix_commands);
  EXPECT_FALSE(v.allocation.normalise_always);
}

Wrench stick_from_joy(const Joy& j) {  // to FRD: Z = -elevate
  Wrench w = Wrench::Zero();
  w << j[0], j[1], -j[5], 0, j[2], j[3];
  return w;
}

TEST(Seed001, TillerDoesWhatTheTextSaysOverAGrid) {
  const Allocator a(seed001_table_vehicle());
  AllocationResult r;
  const double vals[] = {-1, -0.6, -0.2, 0, 0.3, 0.7, 1};
  int cases = 0, scaled = 0;
  for (double f : vals)
    for (double s : vals)
      for (double p : vals)
        for (double y : vals)
          for (double e : vals) {
            const Joy j = {f, s, p, y, 0, e};
            ASSERT_TRUE(a.allocate_manual(stick_from_joy(j), r));
            const Six want = seed001_text(j);
            for (std::size_t i = 0; i < 6; ++i) ASSERT_NEAR(r.command[i], want[i], 1e-12);
            ++cases;
            if (r.scale < 1) ++scaled;
          }
  EXPECT_EQ(cases, 7 * 7 * 7 * 7 * 7);
  EXPECT_GT(scaled, 1000);
}

TEST(Seed001, ItsCodesIndicesGoWrongWhereTillerIsRight) {
  // Elevate down and pitch down, full: F = -1 + -1 = -2, B = -1 + 1 = 0.
  const Joy j = {0, 0, -1, 0, 0, -1};
  const Six code = seed001_code(j), text = seed001_text(j);
  // The code takes Math.max(setpoint[0], setpoint[1]) = max(-2, 0) = 0: no scaling at all, and
  // F is left at -200 % duty.
  EXPECT_EQ(code[0], -2.0);
  EXPECT_EQ(text[0], -1.0);
  EXPECT_EQ(text[3], 0.0);
  const Allocator a(seed001_table_vehicle());
  AllocationResult r;
  ASSERT_TRUE(a.allocate_manual(stick_from_joy(j), r));
  EXPECT_NEAR(r.command[0], -1.0, 1e-12);
  EXPECT_NEAR(r.command[3], 0.0, 1e-12);
  // The vectored group: backward, strafe left and yaw clockwise, full: LF -1, RF -1, LB 1,
  // RB -3. The code's Math.max(setpoint[2..5]) = max(-1, 0 (that is B), 1, -3) = 1 (and LF,
  // index 1, is not even in it): no scaling, RB stays at -300 % duty. The text scales by 3.
  const Joy j2 = {-1, -1, 0, 1, 0, 0};
  const Six code2 = seed001_code(j2), text2 = seed001_text(j2);
  EXPECT_EQ(code2[5], -3.0);
  EXPECT_NEAR(text2[5], -1.0, 1e-12);
  ASSERT_TRUE(a.allocate_manual(stick_from_joy(j2), r));
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(r.command[i], text2[i], 1e-12);
  // Groups are independent: the vertical pair was not scaled by the horizontal overflow.
  const Joy j3 = {-1, -1, 0, 1, 0, 0.5};
  ASSERT_TRUE(a.allocate_manual(stick_from_joy(j3), r));
  EXPECT_NEAR(r.command[0], 0.5, 1e-12);
  EXPECT_NEAR(r.command[3], 0.5, 1e-12);
}

TEST(Seed001, GeometryAllocationFollowsTheDirectionTables) {
  const Allocator a(preset("seed001_rov6"));
  AllocationResult r;
  auto sgn = [](double x) { return std::abs(x) < 1e-9 ? 0 : (x > 0 ? 1 : -1); };
  struct Case {
    int axis;
    double value;
    const Six* arr;
    bool horizontal;
  };
  // forward +X, strafe right +Y, yaw clockwise +N, elevate up -Z, pitch up +M.
  const Case cases[] = {{0, 20, &f_arr, true},
                        {1, 20, &s_arr, true},
                        {5, 2, &y_arr, true},
                        {2, -20, &e_arr, false},
                        {4, 2, &p_arr, false}};
  for (const auto& c : cases) {
    Wrench w = Wrench::Zero();
    w(c.axis) = c.value;
    ASSERT_TRUE(a.allocate(w, r));
    for (std::size_t i = 0; i < 6; ++i) {
      const bool vertical = i == 0 || i == 3;
      if (c.horizontal && vertical) continue;  // compensation of the side-effect pitch
      EXPECT_EQ(sgn(r.thrust[i]), static_cast<int>((*c.arr)[i]))
          << "axis " << c.axis << " thruster " << i;
    }
  }
}

// ------------------------------------------------------------------ seed 004
TEST(Seed004, GeometryGivesTheSeedsTableWithK06FromWhereTheCgIs) {
  const Allocator geo(preset("seed004_usv_x"));
  const auto table = x_drive_table(0.6);
  const int cols[3] = {0, 1, 5};
  for (int c = 0; c < 3; ++c) {
    Wrench e = Wrench::Zero();
    e(cols[c]) = 1.0;
    ThrustVec f = geo.solve_unconstrained(e);
    f /= f.cwiseAbs().maxCoeff();
    for (int i = 0; i < 4; ++i)
      EXPECT_NEAR(f(i), table(i, c), 1e-9) << "column " << c << " row " << i;
  }
}

Vehicle shifted(Vehicle v, double dx) {  // move the CG forward by dx: thrusters move aft
  for (auto& t : v.thrusters) t.position.x() -= dx;
  return v;
}

// The seed's table read as thrust fractions (equal thrust both ways as far as the table is
// concerned), to look at k alone: the preset sends commands, whose -1 is only -100 N.
Vehicle x_table_in_thrust() {
  Vehicle v = preset("seed004_usv_x_table");
  v.allocation.matrix_commands = false;
  v.allocation.normalise_always = false;
  return v;
}

TEST(Seed004, TableOnlyFitsTheHullItWasTunedFor) {
  Wrench strafe = Wrench::Zero();
  strafe(1) = 200;
  AllocationResult r;
  // As tuned: the table's strafe makes no yaw.
  const Allocator table(x_table_in_thrust());
  ASSERT_TRUE(table.allocate(strafe, r));
  EXPECT_NEAR(r.achieved(1), 200, 1e-9);
  EXPECT_NEAR(r.achieved(5), 0, 1e-9);
  EXPECT_NEAR(r.achieved(0), 0, 1e-9);
  // Without the rear reduction (k = 1), strafing turns the boat.
  Vehicle k1 = x_table_in_thrust();
  k1.allocation.matrix.row(2) = x_drive_table(1.0).row(2);
  k1.allocation.matrix.row(3) = x_drive_table(1.0).row(3);
  ASSERT_TRUE(Allocator(k1).allocate(strafe, r));
  EXPECT_LT(r.achieved(5), -50.0);  // rear pair too strong: the stern swings, N m
  EXPECT_TRUE(r.axis_reduced[5]);   // and the status says so
  // CG 0.3 m further forward: the table's k = 0.6 is now wrong, the geometry adapts.
  const Vehicle moved = shifted(x_table_in_thrust(), 0.3);
  ASSERT_TRUE(Allocator(moved).allocate(strafe, r));
  EXPECT_GT(std::abs(r.achieved(5)), 20.0);
  Vehicle moved_geo = shifted(preset("seed004_usv_x"), 0.3);
  const Allocator g(moved_geo);
  ASSERT_TRUE(g.allocate(strafe, r));
  EXPECT_NEAR(r.achieved(5), 0, 1e-9);
  EXPECT_NEAR(r.achieved(1), 200, 1e-9);
  // Its rear reduction is now (0.71 + 1.03) / (2.67 + 1.03).
  EXPECT_NEAR(-r.thrust[2] / r.thrust[0], 1.74 / 3.70, 1e-9);
}

// Seed 004's motor_cmd_generator in its own frame (FLU, torque counter-clockwise), commands.
std::array<double, 4> seed004_table(double fx, double fy, double t, double k) {
  return {-fy + fx - t, fy + fx + t, k * fy + fx - t, -k * fy + fx + t};  // LF RF LR RR
}
// Its text: "the commands to all thrusters are scaled so that the maximum magnitude is 1.0, but
// the ratios of all thruster commands are kept". Word for word: always (any non-zero demand is
// full throttle).
std::array<double, 4> seed004_literal(double fx, double fy, double t, double k) {
  auto c = seed004_table(fx, fy, t, k);
  double mx = 0;
  for (double v : c) mx = std::max(mx, std::abs(v));
  if (mx > 0)
    for (double& v : c) v /= mx;
  return c;
}
// What the text means (a cap that keeps the ratios): divide only when the largest exceeds 1.0.
std::array<double, 4> seed004_text(double fx, double fy, double t, double k) {
  auto c = seed004_table(fx, fy, t, k);
  double mx = 0;
  for (double v : c) mx = std::max(mx, std::abs(v));
  if (mx > 1.0)
    for (double& v : c) v /= mx;
  return c;
}
Wrench stick_from_flu(double fx, double fy, double t) {  // FRD: Y = -Fy, N = -T
  Wrench w = Wrench::Zero();
  w(0) = fx;
  w(1) = -fy;
  w(5) = -t;
  return w;
}

TEST(Seed004, TableCommandsAreTheSeedsTextOverAGrid) {
  const Allocator a(preset("seed004_usv_x_table"));
  AllocationResult r;
  int cases = 0, scaled_down = 0, proportional = 0;
  for (int ix = -10; ix <= 10; ++ix)
    for (int iy = -10; iy <= 10; ++iy)
      for (int it = -10; it <= 10; ++it) {
        const double fx = ix / 10.0, fy = iy / 10.0, t = it / 10.0;
        ASSERT_TRUE(a.allocate_manual(stick_from_flu(fx, fy, t), r));
        const auto want = seed004_text(fx, fy, t, 0.6);
        for (std::size_t i = 0; i < 4; ++i) ASSERT_NEAR(r.command[i], want[i], 1e-12);
        const auto raw = seed004_table(fx, fy, t, 0.6);
        double mx = 0;
        for (double v : raw) mx = std::max(mx, std::abs(v));
        if (mx > 1) ++scaled_down;
        if (mx > 0 && mx < 1) ++proportional;
        ++cases;
      }
  EXPECT_EQ(cases, 21 * 21 * 21);
  EXPECT_GT(scaled_down, 3000);
  EXPECT_GT(proportional, 100);
}

TEST(Seed004, NormalisationIsACapNotAScaleUp) {
  // A tenth of full surge: the seed's "scaled so that the maximum magnitude is 1.0" read word for
  // word would send 1.0 to every motor (a PID's small correction = full throttle); read as the
  // cap it is, it sends 0.1. Tiller's preset: normalise: above_one.
  const auto literal = seed004_literal(0.1, 0, 0, 0.6), text = seed004_text(0.1, 0, 0, 0.6);
  EXPECT_NEAR(literal[0], 1.0, 1e-15);
  EXPECT_NEAR(text[0], 0.1, 1e-15);
  const Allocator a(preset("seed004_usv_x_table"));
  AllocationResult r;
  ASSERT_TRUE(a.allocate_manual(stick_from_flu(0.1, 0, 0), r));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.command[i], 0.1, 1e-12);
  // Over 1: divided by the largest, ratios kept.
  ASSERT_TRUE(a.allocate_manual(stick_from_flu(1.0, 1.0, 0), r));
  const auto big = seed004_text(1.0, 1.0, 0, 0.6);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.command[i], big[i], 1e-12);
  // Zero stays zero (nothing to normalise).
  ASSERT_TRUE(a.allocate_manual(Wrench::Zero(), r));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(r.command[i], 0.0);
  // `normalise: always` is the word-for-word reading, available for comparison.
  Vehicle v = preset("seed004_usv_x_table");
  v.allocation.normalise_always = true;
  const Allocator b(v);
  ASSERT_TRUE(b.allocate_manual(stick_from_flu(0.1, 0, 0), r));
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.command[i], 1.0, 1e-12);
  EXPECT_EQ(r.scale, 1.0);  // a scale-up is not a reduction
}

TEST(Seed004, RatioKeepingNormalisationKeepsCommandRatiosNotThrustRatios) {
  // Full surge + strafe right + yaw clockwise in FRD (the seed's Fx = 1, Fy = -1, T = -1):
  // commands s = (3, -1, 1.4, 0.6); divided by 3: (1, -0.333, 0.467, 0.2), the COMMANDS keep
  // their ratios. With the -100 N reverse side, RF's -0.333 is -33.3 N. (Thrust fractions of
  // max_forward_n would instead give (1, -0.833, ...) in commands.)
  const Allocator a(preset("seed004_usv_x_table"));
  AllocationResult r;
  Wrench j = Wrench::Zero();
  j << 1, 1, 0, 0, 0, 1;
  ASSERT_TRUE(a.allocate_manual(j, r));
  const double want[4] = {1.0, -1.0 / 3, 1.4 / 3, 0.2};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.command[i], want[i], 1e-12);
  EXPECT_NEAR(r.command[1] / r.command[0], -1.0 / 3, 1e-12);
  EXPECT_NEAR(r.thrust[0], 250.0, 1e-9);
  EXPECT_NEAR(r.thrust[1], -100.0 / 3, 1e-9);
  EXPECT_NEAR(r.thrust[2], 1.4 / 3 * 250, 1e-9);
  EXPECT_NEAR(r.scale, 1.0 / 3, 1e-12);
  EXPECT_TRUE(r.saturated[0]);
  // The wrench path uses the same table: tau_norm = tau / full_scale, full_scale from the
  // geometry (X: all four at +1 -> 4 * 250 / sqrt 2).
  EXPECT_NEAR(a.full_scale()(0), 1000 / std::sqrt(2.0), 1e-9);
}

TEST(Seed004, HDriveSideThrustersOnlyStrafeAndNeverTurn) {
  const Allocator a(preset("seed004_usv_h"));
  AllocationResult r;
  Wrench w = Wrench::Zero();
  w(1) = 150;
  ASSERT_TRUE(a.allocate(w, r));
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.thrust[static_cast<std::size_t>(i)], 0, 1e-9);
  EXPECT_NEAR(r.thrust[4], 75, 1e-9);
  EXPECT_NEAR(r.thrust[5], 75, 1e-9);
  EXPECT_NEAR(r.achieved(5), 0, 1e-9);
  w << 400, 0, 0, 0, 0, 300;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_NEAR(r.thrust[4], 0, 1e-9);
  EXPECT_NEAR(r.achieved(0), 400, 1e-9);
  EXPECT_NEAR(r.achieved(5), 300, 1e-9);
  // Everything at once and far too much: one scale for all six (ratios kept).
  w << 5000, 3000, 0, 0, 0, 2000;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_LT(r.scale, 1.0);
  EXPECT_NEAR(r.achieved(1) / r.achieved(0), 0.6, 1e-12);
  EXPECT_NEAR(r.achieved(5) / r.achieved(0), 0.4, 1e-12);
}

}  // namespace
}  // namespace tiller
