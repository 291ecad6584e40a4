// Allocation invariants, for every preset vehicle (issue item 8): with no saturation B*thrust
// equals the demand on the actuated axes; commands stay within [-1, 1] and thrusts within each
// thruster's own limits; direction kept per group under saturation; priority axes met exactly
// when they fit; a reversed thruster changes only its own ESC sign; NaN or out-of-range input
// gives neutral. Seeded random wrenches (std::mt19937, fixed seeds).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "allocation/allocator.hpp"
#include "test_util.hpp"

namespace tiller {
namespace {

using test::preset;
using test::preset_names;
using test::random_wrench;

void expect_within_limits(const Allocator& a, const AllocationResult& r) {
  for (int i = 0; i < a.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Thruster& t = a.vehicle().thrusters[k];
    EXPECT_GE(r.command[k], -1.0);
    EXPECT_LE(r.command[k], 1.0);
    EXPECT_GE(r.thrust[k], t.thrust_min() - 1e-9);
    EXPECT_LE(r.thrust[k], t.thrust_max() + 1e-9);
    EXPECT_NEAR(t.thrust_from_command(r.command[k]), r.thrust[k],
                1e-6 * (1 + std::abs(r.thrust[k])));
  }
}

TEST(Allocation, UnactuatedAxesAreFoundNotInverted) {
  // X Y Z K M N
  const std::map<std::string, std::array<bool, 6>> expected = {
      {"seed000_rov4", {false, false, true, true, true, false}},
      {"seed001_rov6", {false, false, false, true, false, false}},
      {"seed004_usv_x", {false, false, true, true, true, false}},
      {"seed004_usv_x_table", {false, false, true, true, true, false}},
      {"seed004_usv_h", {false, false, true, true, true, false}},
      {"otter", {false, true, true, true, true, false}},
      {"wamv", {false, true, true, true, true, false}},
      {"seed001_rov6_table", {false, false, false, true, false, false}},
      {"bluerov2", {false, false, false, false, true, false}},
      {"blueboat", {false, true, true, true, true, false}}};
  for (const auto& name : preset_names()) {
    const Allocator a(preset(name));
    EXPECT_EQ(a.unactuated(), expected.at(name)) << name;
    AllocationResult r;
    // Asking for an unactuated axis alone gives nothing and no error.
    Wrench w = Wrench::Zero();
    for (int ax = 0; ax < 6; ++ax)
      if (a.unactuated()[static_cast<std::size_t>(ax)]) w(ax) = 10.0;
    ASSERT_TRUE(a.allocate(w, r)) << name;
    for (int i = 0; i < a.size(); ++i) EXPECT_NEAR(r.thrust[static_cast<std::size_t>(i)], 0, 1e-9);
  }
}

TEST(Allocation, UnsaturatedDemandIsMetExactlyForEveryPreset) {
  std::mt19937 rng(1234);
  for (const auto& name : preset_names()) {
    SCOPED_TRACE(name);
    if (test::command_table(preset(name))) continue;
    const Allocator a(preset(name));
    AllocationResult r;
    int checked = 0;
    for (int trial = 0; trial < 500; ++trial) {
      Wrench w = random_wrench(a, rng, 1.0);
      ASSERT_TRUE(a.allocate(w, r));
      if (r.scale < 1.0) {  // bring it inside the feasible set and try again
        w *= 0.9 * r.scale;
        ASSERT_TRUE(a.allocate(w, r));
      }
      ASSERT_EQ(r.scale, 1.0);
      ++checked;
      for (int ax = 0; ax < 6; ++ax) {
        if (a.unactuated()[static_cast<std::size_t>(ax)]) continue;
        EXPECT_NEAR(r.achieved(ax), w(ax), 1e-9 * (1 + w.cwiseAbs().maxCoeff())) << "axis " << ax;
        EXPECT_FALSE(r.axis_reduced[static_cast<std::size_t>(ax)]);
      }
      // Where the minimum-norm solution fits, it is the answer (nothing at a limit); where only
      // the spare thrusters make the demand fit, some thruster may sit at its limit.
      const ThrustVec mn = a.solve_unconstrained(w);
      bool mn_fits = true;
      for (int i = 0; i < a.size(); ++i) {
        const Thruster& t = a.vehicle().thrusters[static_cast<std::size_t>(i)];
        mn_fits = mn_fits && mn(i) < t.thrust_max() && mn(i) > t.thrust_min();
      }
      if (mn_fits && !a.uses_matrix()) {
        for (int i = 0; i < a.size(); ++i) {
          EXPECT_FALSE(r.saturated[static_cast<std::size_t>(i)]);
          EXPECT_NEAR(r.thrust[static_cast<std::size_t>(i)], mn(i), 1e-12 * (1 + std::abs(mn(i))));
        }
      }
      expect_within_limits(a, r);
    }
    EXPECT_EQ(checked, 500);
  }
}

TEST(Allocation, CommandsStayWithinLimitsForEveryStrategyAndHugeDemands) {
  std::mt19937 rng(99);
  for (const auto& name : preset_names()) {
    for (Strategy s : {Strategy::kDirectionPreserving, Strategy::kPrioritised, Strategy::kClip}) {
      Vehicle v = test::with_strategy(preset(name), s);
      if (v.allocation.has_matrix() && s == Strategy::kPrioritised) continue;
      SCOPED_TRACE(name + " " + strategy_name(s));
      const Allocator a(v);
      AllocationResult r;
      for (int trial = 0; trial < 300; ++trial) {
        const Wrench w = random_wrench(a, rng, trial % 2 ? 50.0 : 3.0);
        ASSERT_TRUE(a.allocate(w, r));
        expect_within_limits(a, r);
        // Every actuated axis is either met or flagged as reduced.
        for (int ax = 0; ax < 6; ++ax) {
          const auto k = static_cast<std::size_t>(ax);
          if (a.unactuated()[k]) continue;
          if (!r.axis_reduced[k]) {
            EXPECT_NEAR(r.achieved(ax), w(ax), 1e-6 * (1 + std::abs(w(ax))));
          }
        }
        if (r.scale < 1.0) {
          bool any = false;
          for (int i = 0; i < a.size(); ++i) any = any || r.saturated[static_cast<std::size_t>(i)];
          EXPECT_TRUE(any) << "reduced without a saturated thruster";
        }
      }
    }
  }
}

// Component of x orthogonal to d, relative to |x|.
double off_direction(const Eigen::VectorXd& x, const Eigen::VectorXd& d) {
  if (d.norm() == 0) return x.norm();
  const Eigen::VectorXd dn = d.normalized();
  return (x - x.dot(dn) * dn).norm() / std::max(1e-12, x.norm());
}

TEST(Allocation, DirectionIsKeptPerGroupUnderSaturation) {
  std::mt19937 rng(7);
  for (const auto& name : preset_names()) {
    const Vehicle v = test::with_strategy(preset(name), Strategy::kDirectionPreserving);
    if (test::command_table(v)) continue;
    SCOPED_TRACE(name);
    const Allocator a(v);
    AllocationResult r;
    int saturated = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const Wrench w = random_wrench(a, rng, 5.0);
      ASSERT_TRUE(a.allocate(w, r));
      if (r.scale < 1.0) ++saturated;
      for (const auto& axes : a.group_axes()) {
        Eigen::VectorXd want(axes.size()), got(axes.size());
        for (std::size_t k = 0; k < axes.size(); ++k) {
          want(static_cast<Eigen::Index>(k)) = w(axes[k]);
          got(static_cast<Eigen::Index>(k)) = r.achieved(axes[k]);
        }
        EXPECT_LT(off_direction(got, want), 1e-9);
        EXPECT_GE(got.dot(want), 0.0);                    // same way, not reversed
        EXPECT_LE(got.norm(), want.norm() * (1 + 1e-9));  // scaled down, never up
      }
    }
    EXPECT_GT(saturated, 200);  // the test really exercised saturation
  }
}

TEST(Allocation, ScaleIsTheTrueMaximumOverTheNullSpaceForEveryPreset) {
  // Direction preserving, one group's axes at a time: scale = the largest feasible fraction,
  // computed without the allocator; and the largest achievable along each axis alone.
  std::mt19937 rng(11);
  for (const auto& name : preset_names()) {
    const Vehicle v = test::with_strategy(preset(name), Strategy::kDirectionPreserving);
    if (v.allocation.has_matrix()) continue;  // tables scale their own way (seeds_test)
    SCOPED_TRACE(name);
    const Allocator a(v);
    for (int ax = 0; ax < 6; ++ax) {
      if (a.unactuated()[static_cast<std::size_t>(ax)]) continue;
      for (int s : {1, -1}) {
        const double want = test::brute_max_scale(v, a.unactuated(), s * Wrench::Unit(ax));
        EXPECT_NEAR(a.axis_max(ax, s), want, 1e-9 * want) << "axis " << ax << " sign " << s;
      }
    }
    AllocationResult r;
    int below = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const Wrench w = random_wrench(a, rng, trial % 2 ? 1.5 : 0.7);
      for (const auto& axes : a.group_axes()) {
        Wrench wg = Wrench::Zero();
        for (int ax : axes) wg(ax) = w(ax);
        const double best = test::brute_max_scale(v, a.unactuated(), wg);
        ASSERT_TRUE(a.allocate(wg, r));
        EXPECT_NEAR(r.scale, std::min(1.0, best), 1e-9) << "trial " << trial;
        if (best < 1.0) ++below;
      }
    }
    EXPECT_GT(below, 20);
  }
}

TEST(Allocation, SpareThrustersGiveTheSeed004XDriveItsFullSideways) {
  // Limits -100 / +250 N. The minimum-norm pattern for +Y is (1, -1, -0.6, 0.6) (the seed's
  // k): RF reaches -100 N first, Y = 226.3 N. Adding the null-space pattern (1, 1, -1, -1):
  // (150, -100, -100, 50) N gives X = 0, N = 0 and Y = 200 sqrt 2 = 282.8 N.
  const Vehicle v = preset("seed004_usv_x");
  const Allocator a(v);
  EXPECT_NEAR(a.axis_max(1, 1), 200 * std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(test::brute_max_scale(v, a.unactuated(), Wrench::Unit(1)), 200 * std::sqrt(2.0),
              1e-9);
  Eigen::Vector4d mn = a.solve_unconstrained(Wrench::Unit(1));
  EXPECT_NEAR(100.0 / -mn(1), 226.3, 0.05);  // what the minimum-norm pattern alone reaches
  AllocationResult r;
  Wrench w = Wrench::Zero();
  w(1) = 282.0;  // beyond the pattern, within the boat
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_EQ(r.scale, 1.0);
  EXPECT_NEAR(r.achieved(1), 282.0, 1e-9);
  EXPECT_NEAR(r.achieved(0), 0.0, 1e-9);
  EXPECT_NEAR(r.achieved(5), 0.0, 1e-9);
  // Full sideways stick: the true largest, at (150, -100, -100, 50) N.
  Wrench j = Wrench::Zero();
  j(1) = 1.0;
  ASSERT_TRUE(a.allocate_manual(j, r));
  EXPECT_NEAR(r.achieved(1), 200 * std::sqrt(2.0), 1e-9);
  const double want[4] = {150, -100, -100, 50};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(r.thrust[i], want[i], 1e-9);
  // Prioritised with Y first: a feasible Y = 250 N is met exactly while X and N get the rest.
  Vehicle vp = test::with_strategy(v, Strategy::kPrioritised);
  vp.allocation.priority = {{1}, {0}, {5}, {2}, {3}, {4}};
  const Allocator ap(vp);
  w << 800, 250, 0, 0, 0, 150;
  ASSERT_TRUE(ap.allocate(w, r));
  EXPECT_NEAR(r.achieved(1), 250.0, 1e-9);
  EXPECT_FALSE(r.axis_reduced[1]);
  EXPECT_TRUE(r.axis_reduced[0]);
  expect_within_limits(ap, r);
  w << 0, 250, 0, 0, 0, 0;
  ASSERT_TRUE(ap.allocate(w, r));
  EXPECT_NEAR(r.achieved(1), 250.0, 1e-9);
  EXPECT_NEAR(r.achieved(0), 0.0, 1e-9);
  EXPECT_NEAR(r.achieved(5), 0.0, 1e-9);
  EXPECT_EQ(r.scale, 1.0);
}

TEST(Allocation, ThrustMovesContinuouslyWithTheDemandUnderSaturation) {
  // The spare thrusters' share must not jump between equally good distributions from one
  // demand to the next (a thruster slewing 150 N to make the same wrench): demands swept
  // along random directions from 0 to 3x what the vehicle can do, in 4000 steps.
  std::mt19937 rng(17);
  for (const auto& name : preset_names()) {
    for (Strategy s : {Strategy::kDirectionPreserving, Strategy::kPrioritised}) {
      Vehicle v = test::with_strategy(preset(name), s);
      if (v.allocation.has_matrix()) continue;
      if (s == Strategy::kPrioritised) v.allocation.priority = {{5}, {0}, {1}, {2}, {4}, {3}};
      SCOPED_TRACE(name + " " + strategy_name(s));
      const Allocator a(v);
      double worst = 0, limit = 0;
      for (int i = 0; i < a.size(); ++i)
        limit = std::max(limit, a.vehicle().thrusters[static_cast<std::size_t>(i)].thrust_max());
      for (int trial = 0; trial < 20; ++trial) {
        const Wrench dir = random_wrench(a, rng, 1.0);
        AllocationResult r, prev;
        for (int k = 0; k <= 4000; ++k) {
          ASSERT_TRUE(a.allocate(dir * (3.0 * k / 4000), r));
          if (k > 0)
            for (int i = 0; i < a.size(); ++i)
              worst = std::max(worst, std::abs(r.thrust[static_cast<std::size_t>(i)] -
                                               prev.thrust[static_cast<std::size_t>(i)]));
          prev = r;
        }
      }
      EXPECT_LT(worst, 0.02 * limit) << "largest thrust step between neighbouring demands";
    }
  }
}

TEST(Allocation, LayoutsWithoutSpareThrustersKeepThePseudoInverseExactly) {
  // Otter and WAM-V have no null space: the saturated answer is the pseudo-inverse one,
  // hand-checkable (the golden logs depend on it).
  const Allocator a(preset("otter"));
  Wrench w = Wrench::Zero();
  w << 300, 0, 0, 0, 0, -15;
  AllocationResult r;
  ASSERT_TRUE(a.allocate(w, r));
  // N first: f_p - f_s = -15 / 0.395; X gets the rest with starboard at 119.7.
  EXPECT_EQ(r.thrust[1], 119.7);
  EXPECT_NEAR(r.thrust[0], 119.7 - 15 / 0.395, 1e-12);
}

TEST(Allocation, ClipDistortsTheDirectionWhereDirectionPreservingDoesNot) {
  // Seed 000's ROV, full surge plus full yaw demand.
  const Vehicle v = preset("seed000_rov4");
  const Allocator dp(v), clip(test::with_strategy(v, Strategy::kClip));
  Wrench w = Wrench::Zero();
  w(0) = 2 * dp.axis_max(0, 1);
  w(1) = 0.5 * dp.axis_max(1, 1);
  w(5) = 0.3 * dp.axis_max(5, 1);
  AllocationResult r1, r2;
  ASSERT_TRUE(dp.allocate(w, r1));
  ASSERT_TRUE(clip.allocate(w, r2));
  Eigen::Vector3d want(w(0), w(1), w(5)), got1(r1.achieved(0), r1.achieved(1), r1.achieved(5)),
      got2(r2.achieved(0), r2.achieved(1), r2.achieved(5));
  EXPECT_LT(off_direction(got1, want), 1e-9);
  EXPECT_GT(off_direction(got2, want), 0.05);
}

TEST(Allocation, PriorityAxesAreMetExactlyWhenTheyFit) {
  std::mt19937 rng(42);
  for (const auto& name : preset_names()) {
    Vehicle v = preset(name);
    if (v.allocation.has_matrix()) continue;
    if (v.allocation.strategy != Strategy::kPrioritised) {
      v = test::with_strategy(v, Strategy::kPrioritised);
      v.allocation.priority = {{5}, {0}, {1}, {2}, {4}, {3}};  // yaw, surge, sway, ...
    }
    SCOPED_TRACE(name);
    const Allocator a(v);
    const auto& levels = v.allocation.priority;
    AllocationResult full, first;
    int exact = 0, short_of = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const Wrench w = random_wrench(a, rng, 3.0);
      ASSERT_TRUE(a.allocate(w, full));
      // The first level on its own: the allocator gets exactly the largest feasible fraction
      // of it, computed here without the allocator (vertex enumeration).
      Wrench w1 = Wrench::Zero();
      for (int ax : levels[0]) w1(ax) = w(ax);
      ASSERT_TRUE(a.allocate(w1, first));
      const double best = test::brute_max_scale(v, a.unactuated(), w1);
      ASSERT_GE(best, 0.0);
      if (std::isfinite(best)) {
        EXPECT_NEAR(first.scale, std::min(1.0, best), 1e-9);
      }
      if (best < 1.0) ++short_of;
      if (best >= 1.0 + 1e-9) {
        ++exact;
        for (int ax : levels[0]) {
          if (a.unactuated()[static_cast<std::size_t>(ax)]) continue;
          EXPECT_NEAR(full.achieved(ax), w(ax), 1e-9 * (1 + std::abs(w(ax))));
          EXPECT_FALSE(full.axis_reduced[static_cast<std::size_t>(ax)]);
        }
      }
      expect_within_limits(a, full);
    }
    EXPECT_GT(exact, 50);
    EXPECT_GT(short_of, 20);  // and cases where the first level alone does not fit
  }
}

TEST(Allocation, OtterYawBeforeSurgeHandComputed) {
  // N = -y*Fx: port (y = -0.395) gives +0.395 N m per N. N = 20 N m needs f_p - f_s = 50.63 N;
  // the rest goes to surge: f_p = 119.7 (limit), f_s = 69.07, X = 188.77 N.
  const Allocator a(preset("otter"));
  Wrench w = Wrench::Zero();
  w(0) = 1000;
  w(5) = 20;
  AllocationResult r;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_NEAR(r.achieved(5), 20.0, 1e-9);
  EXPECT_NEAR(r.thrust[0], 119.7, 1e-9);
  EXPECT_NEAR(r.thrust[1], 119.7 - 20.0 / 0.395, 1e-9);
  EXPECT_NEAR(r.achieved(0), 2 * 119.7 - 20.0 / 0.395, 1e-9);
  EXPECT_TRUE(r.axis_reduced[0]);
  EXPECT_FALSE(r.axis_reduced[5]);
  EXPECT_TRUE(r.saturated[0]);
  EXPECT_FALSE(r.saturated[1]);
  // Command through the quadratic curve: u = sqrt(f / 119.7).
  EXPECT_NEAR(r.command[0], 1.0, 1e-12);
  EXPECT_NEAR(r.command[1], std::sqrt(r.thrust[1] / 119.7), 1e-12);
}

TEST(Allocation, WamvUsesEachSideOfItsEnginesLimits) {
  // Engines at y = -+1.03 m, +250 / -100 N. N = 100 N m needs f_l - f_r = 97.09 N; surge gets
  // the rest: f_l = 250, f_r = 152.91, X = 402.91 N. Full reverse: -100 N each.
  const Allocator a(preset("wamv"));
  Wrench w = Wrench::Zero();
  w(0) = 600;
  w(5) = 100;
  AllocationResult r;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_NEAR(r.achieved(5), 100, 1e-9);
  EXPECT_NEAR(r.thrust[0], 250, 1e-9);
  EXPECT_NEAR(r.thrust[1], 250 - 100 / 1.03, 1e-9);
  EXPECT_NEAR(r.command[1], (250 - 100 / 1.03) / 250, 1e-12);
  w << -500, 0, 0, 0, 0, 0;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_NEAR(r.achieved(0), -200, 1e-9);
  EXPECT_NEAR(r.command[0], -1.0, 1e-12);
  EXPECT_NEAR(r.command[1], -1.0, 1e-12);
  EXPECT_TRUE(r.axis_reduced[0]);
  EXPECT_NEAR(a.axis_max(0, 1), 500, 1e-9);
  EXPECT_NEAR(a.axis_max(0, -1), 200, 1e-9);
}

TEST(Allocation, ReversedThrusterChangesOnlyItsOwnEscSign) {
  std::mt19937 rng(5);
  for (const auto& name : preset_names()) {
    const Vehicle v = preset(name);
    const Allocator a(v);
    for (int k = 0; k < v.size(); ++k) {
      SCOPED_TRACE(name + " thruster " + v.thrusters[static_cast<std::size_t>(k)].name);
      Vehicle vr = v;
      vr.thrusters[static_cast<std::size_t>(k)].reversed = true;
      const Allocator ar(vr);
      for (int trial = 0; trial < 20; ++trial) {
        Wrench w = random_wrench(a, rng, 0.2);
        AllocationResult r, rr;
        ASSERT_TRUE(a.allocate(w, r));
        ASSERT_TRUE(ar.allocate(w, rr));
        if (r.scale < 1 || rr.scale < 1) continue;  // limits differ once saturated
        if (test::command_table(v)) {
          // A table of commands: Tiller's command (+ = along direction) is the table's, the
          // same for the reversed thruster; only that ESC's sign flips (in tiller-esc).
          for (int i = 0; i < v.size(); ++i)
            EXPECT_EQ(rr.command[static_cast<std::size_t>(i)],
                      r.command[static_cast<std::size_t>(i)]);
          continue;
        }
        for (int i = 0; i < v.size(); ++i) {
          const auto s = static_cast<std::size_t>(i);
          const Thruster& t = v.thrusters[s];
          // What the ESC sends to each motor: tiller-esc flips reversed thrusters.
          const double esc = r.command[s];
          const double esc_r = i == k ? -rr.command[s] : rr.command[s];
          EXPECT_NEAR(rr.thrust[s], r.thrust[s], 1e-9);
          if (i != k) {
            EXPECT_NEAR(esc_r, esc, 1e-12);
          } else {
            // The motor now pushes the other way round to give the same thrust.
            EXPECT_NEAR(t.curve.thrust(esc_r), -t.curve.thrust(esc), 1e-6);
            if (t.curve.max_forward_n() == t.curve.max_reverse_n() &&
                t.curve.kind() != ThrustCurve::Kind::kTable) {
              EXPECT_NEAR(esc_r, -esc, 1e-9);  // symmetric curve: exactly a sign flip
            }
          }
        }
      }
    }
  }
}

TEST(Allocation, NanOrOutOfRangeGivesNeutral) {
  for (const auto& name : preset_names()) {
    const Allocator a(preset(name));
    AllocationResult r;
    Wrench w = Wrench::Zero();
    w(0) = 10;
    ASSERT_TRUE(a.allocate(w, r));
    w(1) = std::nan("");
    EXPECT_FALSE(a.allocate(w, r));
    for (int i = 0; i < a.size(); ++i) EXPECT_EQ(r.command[static_cast<std::size_t>(i)], 0.0);
    w(1) = 2e5;
    EXPECT_FALSE(a.allocate(w, r));
    w(1) = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(a.allocate(w, r));
    Wrench j = Wrench::Zero();
    j(0) = 1.5;
    EXPECT_FALSE(a.allocate_manual(j, r));
    for (int i = 0; i < a.size(); ++i) EXPECT_EQ(r.command[static_cast<std::size_t>(i)], 0.0);
    j(0) = std::nan("");
    EXPECT_FALSE(a.allocate_manual(j, r));
  }
}

TEST(Allocation, CoupledGroupsAreSolvedInOrderSoTheRovDoesNotPitch) {
  // Seed 001: the vectored thrusters sit 0.085 m below the CG, so surge thrust pitches the ROV
  // (M = 0.085 X). The horizontal group is solved first and the vertical pair cancels it.
  const Allocator a(preset("seed001_rov6"));
  ASSERT_EQ(a.group_axes().size(), 2u);
  EXPECT_EQ(a.group_axes()[0], (std::vector<int>{0, 1, 5}));  // horizontal: X Y N
  EXPECT_EQ(a.group_axes()[1], (std::vector<int>{2, 4}));     // vertical: Z M
  Wrench w = Wrench::Zero();
  w(0) = 40;
  AllocationResult r;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_NEAR(r.achieved(0), 40, 1e-9);
  EXPECT_NEAR(r.achieved(4), 0, 1e-9);
  EXPECT_NEAR(r.thrust[0], -r.thrust[3], 1e-9);  // F and B opposite: a pure pitch couple
  EXPECT_GT(std::abs(r.thrust[0]), 0.1);
  // Saturating the horizontal group leaves depth and pitch exact.
  w(0) = 1000;
  w(5) = 30;
  w(2) = -20;
  ASSERT_TRUE(a.allocate(w, r));
  EXPECT_LT(r.scale, 1.0);
  EXPECT_NEAR(r.achieved(2), -20, 1e-9);
  EXPECT_NEAR(r.achieved(4), 0, 1e-9);
  EXPECT_FALSE(r.axis_reduced[2]);
  EXPECT_TRUE(r.axis_reduced[0]);
  EXPECT_NEAR(r.achieved(5) / r.achieved(0), 30.0 / 1000.0, 1e-12);
}

TEST(Allocation, GroupsActingOnOneAxisIndependentlyAreRefused) {
  Vehicle v = preset("otter");
  v.thrusters[1].group = "other";  // both propellers make surge on their own
  try {
    Allocator a(v);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("both act on axis X"), std::string::npos) << m;
    EXPECT_NE(m.find("config/vehicles/otter.yaml: thrusters[1].group"), std::string::npos) << m;
    EXPECT_NE(m.find("thrusters[0].group"), std::string::npos) << m;
    EXPECT_NE(m.find("expected those thrusters in one group"), std::string::npos) << m;
  }
}

TEST(Allocation, MixingColumnThatProducesNothingIsRefusedNamingFileAndKey) {
  Vehicle v = preset("seed004_usv_x_table");
  v.allocation.matrix.col(2).setZero();  // the N column
  try {
    Allocator a(v);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("config/vehicles/seed004_usv_x_table.yaml: allocation.mixing.x_drive"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("column 2 (axis N) produces nothing"), std::string::npos) << m;
    EXPECT_NE(m.find("expected"), std::string::npos) << m;
  }
  Vehicle r = preset("seed001_rov6_table");
  r.allocation.matrix.col(0).setZero();  // X
  try {
    Allocator a(r);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("seed001_rov6_table.yaml: allocation.mixing.rows: column 0 (axis X)"),
              std::string::npos)
        << m;
  }
}

}  // namespace
}  // namespace tiller
