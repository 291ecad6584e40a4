// Vehicle descriptions and thrust curves: every preset file loads; the T200 table reproduces
// Blue Robotics' T200 numbers (docs/adding-a-vehicle.md); forward and inverse maps round-trip;
// reversal swaps the limits; the loader refuses bad files with the file, the key and what was
// expected.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "vehicle/thrust_curve.hpp"
#include "vehicle/vehicle.hpp"

namespace tiller {
namespace {

const std::string kVehicles = std::string(TILLER_SOURCE_DIR) + "/config/vehicles/";
constexpr double kKgf = 9.80665;

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const config::Error& e) {
    return e.what();
  }
  return "(no error)";
}

struct Preset {
  const char* file;
  int thrusters;
};
const Preset kPresets[] = {
    {"seed000_rov4", 4},  {"seed001_rov6", 6}, {"seed004_usv_x", 4}, {"seed004_usv_x_table", 4},
    {"seed004_usv_h", 6}, {"otter", 2},        {"wamv", 2},          {"seed001_rov6_table", 6},
    {"bluerov2", 6}};

TEST(Vehicle, EveryPresetLoads) {
  for (const auto& p : kPresets) {
    SCOPED_TRACE(p.file);
    const Vehicle v = load_vehicle_file(kVehicles + p.file + ".yaml");
    EXPECT_EQ(v.name, p.file);
    ASSERT_EQ(v.size(), p.thrusters);
    for (const auto& t : v.thrusters) {
      EXPECT_NEAR(t.direction.norm(), 1.0, 1e-12);
      EXPECT_GT(t.thrust_max(), 0);
      EXPECT_LT(t.thrust_min(), 0);
      EXPECT_LE(t.max_forward_n, t.curve.max_forward_n() * (1 + 1e-6));
    }
    const Eigen::MatrixXd b = v.effectiveness();
    EXPECT_EQ(b.rows(), 6);
    EXPECT_EQ(b.cols(), p.thrusters);
  }
}

TEST(Vehicle, BlueRov2EffectivenessMatrixIsTheHandComputedOne) {
  // Column i = [d; r x d] (FRD, about the CG), a = cos 45 deg. Horizontal thrusters at
  // (+-0.156, +-0.111, 0.085): r x d = (r_y d_z - r_z d_y, r_z d_x - r_x d_z, r_x d_y - r_y d_x),
  // e.g. FL, r = (0.156, -0.111, 0.085), d = (a, a, 0): (-0.085 a, 0.085 a, 0.267 a). Vertical VL,
  // r = (0, -0.111, 0), d = (0, 0, -1): (0.111, 0, 0), so pushing up on the left rolls right (+K).
  const Vehicle v = load_vehicle_file(kVehicles + "bluerov2.yaml");
  const double a = 0.70710678;
  const double x = 0.085 * a, z = 0.267 * a;
  Eigen::MatrixXd want(6, 6);
  //         FL   FR   RL   RR    VL      VR
  want << a, a, a, a, 0, 0,         // X: every horizontal thruster pushes forward
      a, -a, -a, a, 0, 0,           // Y
      0, 0, 0, 0, -1, -1,           // Z: both vertical thrusters push up
      -x, x, x, -x, 0.111, -0.111,  // K: the horizontal ones' side effect, and the pair
      x, x, x, x, 0, 0,             // M: forward thrust below the CG pitches the nose up
      z, -z, z, -z, 0, 0;           // N
  const char* order[6] = {"FL", "FR", "RL", "RR", "VL", "VR"};
  for (int k = 0; k < 6; ++k) ASSERT_EQ(v.index_of(order[k]), k);
  EXPECT_LT((v.effectiveness() - want).cwiseAbs().maxCoeff(), 1e-8) << v.effectiveness();
  for (const auto& t : v.thrusters) {
    EXPECT_NEAR(t.max_forward_n, 3.71 * kKgf, 0.01);  // T200 at 12 V, datasheet
    EXPECT_NEAR(t.max_reverse_n, 2.90 * kKgf, 0.01);
  }
}

TEST(Vehicle, Seed001DirectionsFollowTheSeedTablesForPureThrust) {
  // Columns of B for a positive command: forward [0,1,1,0,1,1] -> +X for LF RF LB RB; strafe
  // right [0,1,-1,0,-1,1] -> sign of Y; yaw clockwise [0,1,-1,0,1,-1] -> sign of N.
  const Vehicle v = load_vehicle_file(kVehicles + "seed001_rov6.yaml");
  const Eigen::MatrixXd b = v.effectiveness();
  const int f[6] = {0, 1, 1, 0, 1, 1}, s[6] = {0, 1, -1, 0, -1, 1}, y[6] = {0, 1, -1, 0, 1, -1};
  const int e[6] = {1, 0, 0, 1, 0, 0}, p[6] = {1, 0, 0, -1, 0, 0};
  const char* order[6] = {"F", "LF", "RF", "B", "LB", "RB"};
  for (int k = 0; k < 6; ++k) {
    const int i = v.index_of(order[k]);
    ASSERT_EQ(i, k);
    auto sgn = [](double x) { return std::abs(x) < 1e-9 ? 0 : (x > 0 ? 1 : -1); };
    EXPECT_EQ(sgn(b(0, i)), f[k]) << order[k];
    EXPECT_EQ(sgn(b(1, i)), s[k]) << order[k];
    EXPECT_EQ(sgn(b(5, i)), y[k]) << order[k];
    EXPECT_EQ(sgn(-b(2, i)), e[k]) << order[k];  // elevation up = -Z (FRD)
    // Pitch up = +M (FRD). The vectored thrusters sit 0.085 m below the CG, so their column
    // has a side-effect pitch; the allocator compensates it (test/allocation).
    if (k == 0 || k == 3) {
      EXPECT_EQ(sgn(b(4, i)), p[k]) << order[k];
    }
  }
}

TEST(ThrustCurve, T200TableMatchesHardwareData) {
  const ThrustCurve c = ThrustCurve::preset("t200_12v");
  // 1100 us -> u = -1; 1900 -> 1; 1600 -> 0.25; 1300 -> -0.5 (u = (us - 1500) / 400).
  EXPECT_NEAR(c.thrust(-1.0), -2.90 * kKgf, 1e-12);
  EXPECT_NEAR(c.thrust(1.0), 3.71 * kKgf, 1e-12);
  EXPECT_NEAR(c.thrust(0.25), 0.39 * kKgf, 1e-12);
  EXPECT_NEAR(c.thrust(-0.5), -1.02 * kKgf, 1e-12);
  EXPECT_NEAR(c.thrust(0.5), 1.28 * kKgf, 1e-12);
  // Dead band 1464..1536 us.
  EXPECT_EQ(c.thrust(0.0), 0.0);
  EXPECT_EQ(c.thrust(0.08), 0.0);
  EXPECT_EQ(c.thrust(-0.09), 0.0);
  EXPECT_GT(c.thrust(0.1), 0.0);
  // Reverse about 78 % of forward (T200 data, docs/adding-a-vehicle.md).
  EXPECT_NEAR(c.max_reverse_n() / c.max_forward_n(), 0.78, 0.01);
  // Half command gives about a third of full thrust.
  EXPECT_NEAR(c.thrust(0.5) / c.thrust(1.0), 0.345, 0.01);
  // Inverse: exact at the data points, neutral stays neutral, clamps beyond the range.
  EXPECT_NEAR(c.command(2.46 * kKgf), 0.75, 1e-12);
  EXPECT_NEAR(c.command(-1.95 * kKgf), -0.75, 1e-12);
  EXPECT_EQ(c.command(0.0), 0.0);
  EXPECT_EQ(c.command(1e6), 1.0);
  EXPECT_EQ(c.command(-1e6), -1.0);
  EXPECT_EQ(c.command(std::nan("")), 0.0);
  // Smallest positive thrust needs a command past the dead band edge (0.09).
  EXPECT_NEAR(c.command(1e-9), 0.09, 1e-6);
}

// The 12 and 16 V sheets of Blue Robotics' T200 data (vehicle/t200_tables.hpp) and their blend:
// exact at the sheets' points, 14.8 V between them, the table within 1.1 % of the 14 V sheet it
// was not built from (4.53 kgf at 1900 us), clamped outside 12..16 V, the inverse exact.
TEST(ThrustCurve, T200VoltageTablesMatchTheSheets) {
  const ThrustCurve c16 = ThrustCurve::preset("t200_16v");
  EXPECT_FALSE(c16.voltage_dependent());
  EXPECT_NEAR(c16.thrust(1.0), 5.25 * kKgf, 1e-12);    // 1900 us
  EXPECT_NEAR(c16.thrust(-1.0), -4.07 * kKgf, 1e-12);  // 1100 us
  EXPECT_NEAR(c16.thrust(0.85), 4.25 * kKgf, 1e-12);   // 1840 us
  EXPECT_NEAR(c16.command(4.25 * kKgf), 0.85, 1e-12);
  EXPECT_EQ(c16.thrust(0.06), 0.0);  // 1524 us: inside 16 V's dead band 1472..1528
  EXPECT_GT(c16.thrust(0.08), 0.0);  // 1532 us: 0.04 kgf
  ThrustCurve v = ThrustCurve::preset("t200");
  ASSERT_TRUE(v.voltage_dependent());
  EXPECT_EQ(v.supply_voltage(), 16.0);  // until told: the least thrust for a command
  EXPECT_NEAR(v.thrust(0.85), 4.25 * kKgf, 1e-12);
  v.set_supply_voltage(12.0);
  EXPECT_NEAR(v.thrust(0.85), 3.01 * kKgf, 1e-12);  // the 12 V sheet at 1840 us
  EXPECT_NEAR(v.command(3.01 * kKgf), 0.85, 1e-12);
  EXPECT_NEAR(v.thrust(1.0), 3.71 * kKgf, 1e-12);
  v.set_supply_voltage(14.0);
  EXPECT_NEAR(v.thrust(1.0) / kKgf, 4.48, 1e-9);  // the 14 V sheet says 4.53: 1.1 % low
  const ThrustCurve c148 = ThrustCurve::preset("t200_14v8");
  EXPECT_NEAR(c148.thrust(1.0), (0.3 * 3.71 + 0.7 * 5.25) * kKgf, 1e-12);
  v.set_supply_voltage(9.0);
  EXPECT_EQ(v.supply_voltage(), 12.0);
  v.set_supply_voltage(std::nan(""));
  EXPECT_EQ(v.supply_voltage(), 12.0);
  v.set_supply_voltage(25.0);
  EXPECT_EQ(v.supply_voltage(), 16.0);
  // Round trips at every half volt, both directions.
  for (double volts = 12.0; volts <= 16.0; volts += 0.5) {
    v.set_supply_voltage(volts);
    for (double f = -39.0; f <= 50.0; f += 1.0) {
      if (f < v.max_forward_n() && f > -v.max_reverse_n() && f != 0.0) {
        EXPECT_NEAR(v.thrust(v.command(f)), f, 1e-9) << volts << " V, " << f << " N";
      }
    }
  }
  // A curve that does not depend on the voltage ignores it.
  ThrustCurve c12 = ThrustCurve::preset("t200_12v");
  c12.set_supply_voltage(16.0);
  EXPECT_NEAR(c12.thrust(1.0), 3.71 * kKgf, 1e-12);
  EXPECT_THROW(ThrustCurve::voltage_table({-1, 0, 1}, {-1, 0, 1}, 16, {-2, 0, 2}, 12),
               std::invalid_argument);
}

TEST(ThrustCurve, RoundTripsForEveryKind) {
  const ThrustCurve curves[] = {ThrustCurve::preset("t200_12v"),
                                ThrustCurve::preset("t200_poly"),
                                ThrustCurve::linear(250, 100),
                                ThrustCurve::quadratic(119.7, 66.7),
                                ThrustCurve::table({-1, -0.2, 0, 0.3, 1}, {-20, -3, 0, 5, 30}),
                                ThrustCurve::polynomial({0, 2.0, 0, 1.0})};
  for (const auto& c : curves) {
    SCOPED_TRACE(c.description());
    for (int k = -200; k <= 200; ++k) {
      const double f = k / 200.0 * (k < 0 ? c.max_reverse_n() : c.max_forward_n());
      const double u = c.command(f);
      EXPECT_GE(u, -1.0);
      EXPECT_LE(u, 1.0);
      EXPECT_NEAR(c.thrust(u), f, 1e-9 * (1 + std::abs(f)));
    }
    // Forward map is monotone over the usable range.
    double prev = -1e300;
    for (int k = 0; k <= 400; ++k) {
      const double u = c.min_command() + (c.max_command() - c.min_command()) * k / 400.0;
      EXPECT_GE(c.thrust(u), prev);
      prev = c.thrust(u);
    }
  }
}

TEST(ThrustCurve, T200PolynomialUsesOnlyItsMonotonicPart) {
  const ThrustCurve c = ThrustCurve::preset("t200_poly");
  // F(1) = -140.3 + 389.9 - 404.1 + 176 + 8.9 = 30.4 N, but F'(1) < 0: the peak is earlier.
  EXPECT_LT(c.max_command(), 1.0);
  EXPECT_GT(c.max_command(), 0.9);
  EXPECT_GT(c.max_forward_n(), 30.4);
  EXPECT_NEAR(c.max_forward_n(), c.max_reverse_n(), 1e-9);  // odd polynomial
  EXPECT_NEAR(c.thrust(0.5), -140.3 / 512 + 389.9 / 128 - 404.1 / 32 + 176.0 / 8 + 8.9 / 2, 1e-12);
}

TEST(ThrustCurve, QuadraticIsKnTimesAbsN) {
  const ThrustCurve c = ThrustCurve::quadratic(119.7, 66.7);
  EXPECT_NEAR(c.thrust(0.5), 119.7 * 0.25, 1e-12);
  EXPECT_NEAR(c.thrust(-0.5), -66.7 * 0.25, 1e-12);
  EXPECT_NEAR(c.command(119.7 / 4), 0.5, 1e-12);
}

TEST(Thruster, ReversalSwapsTheSidesAndRoundTrips) {
  Thruster t;
  t.curve = ThrustCurve::preset("t200_12v");
  t.max_forward_n = t.curve.max_forward_n();
  t.max_reverse_n = t.curve.max_reverse_n();
  EXPECT_NEAR(t.thrust_max(), 3.71 * kKgf, 1e-9);
  t.reversed = true;
  // Pushing along `direction` now uses the motor's reverse side.
  EXPECT_NEAR(t.thrust_max(), 2.90 * kKgf, 1e-9);
  EXPECT_NEAR(t.thrust_min(), -3.71 * kKgf, 1e-9);
  for (double f : {-30.0, -5.0, 0.0, 4.0, 25.0}) {
    const double u = t.command_from_thrust(f);
    EXPECT_NEAR(t.thrust_from_command(u), f, 1e-9);
    // The motor sees -u (tiller-esc flips it) and pushes along its own axis, i.e. against
    // `direction`: motor thrust = curve(-u) = -f.
    EXPECT_NEAR(t.curve.thrust(-u), -f, 1e-9);
  }
}

const char* kGood = R"(name: test
thrusters:
  - {name: a, position: [0.5, 0, 0], direction: [1, 0, 0], max_forward_n: 30, max_reverse_n: 20,
     curve: t200_12v, group: g, reversed: false}
  - {name: b, position: [-0.5, 0.2, 0], direction: [0, 1, 0], max_forward_n: 10, max_reverse_n: 10,
     curve: {table: {command: [-1, 0, 1], thrust_n: [-10, 0, 10]}}, group: g, reversed: true}
allocation:
  strategy: prioritised
  priority: [N, [X, Y]]
dynamics:
  mass: 12
  whatever: [1, 2, 3]
)";

Vehicle parse(const std::string& text) {
  const auto root = config::Value::parse(text, "veh.yaml");
  Vehicle v = load_vehicle(root);
  root.check_all_used();
  return v;
}

TEST(VehicleLoader, ReadsAllFieldsAndLeavesDynamicsToTheSimulator) {
  const Vehicle v = parse(kGood);
  ASSERT_EQ(v.size(), 2);
  EXPECT_TRUE(v.thrusters[1].reversed);
  EXPECT_EQ(v.thrusters[1].group, "g");
  EXPECT_EQ(v.allocation.strategy, Strategy::kPrioritised);
  ASSERT_EQ(v.allocation.priority.size(), 5u);  // N, [X Y], then Z, K, M appended
  EXPECT_EQ(v.allocation.priority[0], std::vector<int>{5});
  EXPECT_EQ(v.allocation.priority[1], (std::vector<int>{0, 1}));
  const Eigen::MatrixXd b = v.effectiveness();
  EXPECT_NEAR(b(5, 1), -0.5, 1e-12);  // N = x*Fy - y*Fx for b
  EXPECT_NEAR(b(5, 0), 0.0, 1e-12);
}

TEST(VehicleLoader, RefusesBadFilesNamingFileKeyAndExpectation) {
  auto err = [&](const std::string& from, const std::string& to) {
    std::string text = kGood;
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
    return error_of([&] { parse(text); });
  };
  std::string e = err("direction: [1, 0, 0]", "direction: [1, 1, 0]");
  EXPECT_NE(e.find("veh.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("thrusters[0].direction"), std::string::npos) << e;
  EXPECT_NE(e.find("unit vector"), std::string::npos) << e;
  e = err("max_forward_n: 30", "max_forward_n: 40");
  EXPECT_NE(e.find("thrusters[0].max_forward_n"), std::string::npos) << e;
  EXPECT_NE(e.find("curve's forward thrust"), std::string::npos) << e;
  e = err("curve: t200_12v", "curve: t300");
  EXPECT_NE(e.find("thrusters[0].curve"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown thrust curve preset"), std::string::npos) << e;
  e = err("name: b", "name: a");
  EXPECT_NE(e.find("used only once"), std::string::npos) << e;
  e = err("group: g, reversed: false", "group: g, reversd: false");
  EXPECT_NE(e.find("reversed"), std::string::npos) << e;
  e = err("priority: [N, [X, Y]]", "priority: [N, W]");
  EXPECT_NE(e.find("allocation.priority"), std::string::npos) << e;
  e = err("thrust_n: [-10, 0, 10]", "thrust_n: [-10, 1, 10]");
  EXPECT_NE(e.find("thrust at command 0 must be 0"), std::string::npos) << e;
  e = err("strategy: prioritised", "strategy: best");
  EXPECT_NE(e.find("allocation.strategy"), std::string::npos) << e;
  e = err("  - {name: a", "  - {nme: x, name: a");
  EXPECT_NE(e.find("nme"), std::string::npos) << e;
}

const char* kTable = R"(name: table
thrusters:
  - {name: a, position: [0.5, 0, 0], direction: [1, 0, 0], max_forward_n: 30, max_reverse_n: 20,
     curve: t200_12v, group: g, reversed: false}
  - {name: b, position: [-0.5, 0.2, 0], direction: [0, 1, 0], max_forward_n: 10, max_reverse_n: 10,
     curve: {table: {command: [-1, 0, 1], thrust_n: [-10, 0, 10]}}, group: g, reversed: true}
allocation:
  strategy: direction_preserving
  mixing:
    units: command
    normalise: above_one
    axes: [X, Y]
    rows:
      a: [1, 0]
      b: [0, 1]
)";

TEST(VehicleLoader, ReadsAMixingTable) {
  const Vehicle v = parse(kTable);
  ASSERT_TRUE(v.allocation.has_matrix());
  EXPECT_EQ(v.allocation.matrix_axes, (std::vector<int>{0, 1}));
  EXPECT_TRUE(v.allocation.matrix_commands);
  EXPECT_FALSE(v.allocation.normalise_always);
  EXPECT_EQ(v.allocation.matrix(1, 1), 1.0);
  // The seed presets: seed 001 (rows) and seed 004 (x_drive), both in commands.
  const Vehicle s1 = load_vehicle_file(kVehicles + "seed001_rov6_table.yaml");
  EXPECT_TRUE(s1.allocation.matrix_commands);
  EXPECT_FALSE(s1.allocation.normalise_always);
  EXPECT_EQ(s1.allocation.matrix_axes, (std::vector<int>{0, 1, 2, 4, 5}));
  const Vehicle s4 = load_vehicle_file(kVehicles + "seed004_usv_x_table.yaml");
  EXPECT_TRUE(s4.allocation.matrix_commands);
  EXPECT_FALSE(s4.allocation.normalise_always);  // the seed's "max magnitude 1.0" is a cap
  // `normalise: always` and `units: thrust_fraction` are read too.
  std::string t = kTable;
  t.replace(t.find("normalise: above_one"), 20, "normalise: always");
  t.replace(t.find("units: command"), 14, "units: thrust_fraction");
  const Vehicle w = parse(t);
  EXPECT_TRUE(w.allocation.normalise_always);
  EXPECT_FALSE(w.allocation.matrix_commands);
}

TEST(VehicleLoader, RefusesBadMixingRowsNamingFileKeyAndExpectation) {
  auto err = [&](const std::string& from, const std::string& to) {
    std::string text = kTable;
    const auto pos = text.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    text.replace(pos, from.size(), to);
    return error_of([&] { parse(text); });
  };
  // A row named after no thruster.
  std::string e = err("      b: [0, 1]", "      b: [0, 1]\n      c: [1, 1]");
  EXPECT_NE(e.find("veh.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("allocation.mixing.rows.c"), std::string::npos) << e;
  EXPECT_NE(e.find("a row named after a thruster of this vehicle"), std::string::npos) << e;
  // A thruster without a row.
  e = err("      b: [0, 1]\n", "");
  EXPECT_NE(e.find("veh.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("allocation.mixing.rows"), std::string::npos) << e;
  EXPECT_NE(e.find("one row per thruster (missing: b)"), std::string::npos) << e;
  // A row of the wrong length.
  e = err("a: [1, 0]", "a: [1, 0, 0]");
  EXPECT_NE(e.find("veh.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("allocation.mixing.rows.a"), std::string::npos) << e;
  EXPECT_NE(e.find("2 numbers"), std::string::npos) << e;
  // An X-drive list naming a thruster twice (another left without a row) is refused.
  {
    std::ifstream f(kVehicles + "seed004_usv_x_table.yaml");
    std::string x((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const std::string list = "thrusters: [LF, RF, LR, RR]";
    ASSERT_NE(x.find(list), std::string::npos);
    x.replace(x.find(list), list.size(), "thrusters: [LF, RF, LR, LR]");
    e = error_of([&] { parse(x); });
    EXPECT_NE(e.find("veh.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find("x_drive.thrusters[3]"), std::string::npos) << e;
    EXPECT_NE(e.find("'LR' is repeated"), std::string::npos) << e;
  }
  // Units and normalisation must be said.
  e = err("    units: command\n", "");
  EXPECT_NE(e.find("allocation.mixing.units"), std::string::npos) << e;
  EXPECT_NE(e.find("command"), std::string::npos) << e;
  e = err("normalise: above_one", "normalise: sometimes");
  EXPECT_NE(e.find("allocation.mixing.normalise"), std::string::npos) << e;
  EXPECT_NE(e.find("always"), std::string::npos) << e;
  e = err("axes: [X, Y]", "axes: [X, W]");
  EXPECT_NE(e.find("allocation.mixing.axes"), std::string::npos) << e;
  EXPECT_NE(e.find("an axis name"), std::string::npos) << e;
}

}  // namespace
}  // namespace tiller
