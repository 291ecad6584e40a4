// The BlueROV2-class vehicle's simulator model (config/vehicles/bluerov2.yaml): slightly buoyant
// by the hand-computed amount and rising at the speed its heave damping gives; under full forward
// thrust of its four vectored T200s (4 * 36.38 N * cos 45 = 102.90 N) it settles at the surge
// speed where the damping 13.7 u + 141 u^2 balances the thrust (and the net buoyancy's share
// along the pitched body x axis), leaning nose up less than 25 degrees and not turning.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/angles.hpp"
#include "model_fixture.hpp"
#include "sim/environment.hpp"
#include "sim/vessel_model.hpp"

namespace tiller::sim {
namespace {

void run_for(VesselModel& m, double seconds, double dt = 0.01) {
  const Environment env;
  const int n = static_cast<int>(std::lround(seconds / dt));
  for (int i = 0; i < n; ++i) m.step(dt, env);
}

// Positive root of lin v + quad v^2 = f.
double root(double f, double lin, double quad) {
  return (-lin + std::sqrt(lin * lin + 4 * quad * f)) / (2 * quad);
}

TEST(BlueRov2Model, SlightlyBuoyantAndRisesAtTheHeaveDampingsSpeed) {
  const auto p = test::dynamics_of("bluerov2");
  // B = 1000 * 9.81 * 0.013024 = 127.765 N, W = 12.812 * 9.81 = 125.686 N.
  EXPECT_NEAR(p.buoyancy_n, 127.765, 1e-3);
  EXPECT_NEAR(p.weight_n, 125.686, 1e-3);
  EXPECT_NEAR(p.buoyancy_n - p.weight_n, 2.080, 1e-3);
  EXPECT_LT((p.buoyancy_n - p.weight_n) / p.weight_n, 0.02);
  auto m = test::model_of("bluerov2");
  m.reset(Vector6::Zero(), Vector6::Zero());
  run_for(m, 30.0);
  // Rises (w < 0 in FRD) at the root of 33 w + 190 w^2 = 2.080: 0.0491 m/s, upright.
  EXPECT_NEAR(m.nu()[2], -root(p.buoyancy_n - p.weight_n, 33.0, 190.0), 1e-6);
  EXPECT_NEAR(m.nu()[2], -0.0491, 1e-4);
  EXPECT_NEAR(m.eta()[3], 0.0, 1e-12);
  EXPECT_NEAR(m.eta()[4], 0.0, 1e-12);
}

TEST(BlueRov2Model, FullForwardThrustSettlesWhereTheDampingBalancesIt) {
  const auto p = test::dynamics_of("bluerov2");
  auto m = test::model_of("bluerov2");
  m.reset(Vector6::Zero(), Vector6::Zero());
  for (int i = 0; i < 4; ++i) m.set_thrust_target(i, 36.38);  // FL FR RL RR, full forward
  run_for(m, 60.0);
  const double x_thrust = 4 * 36.38 * std::sqrt(0.5);
  EXPECT_NEAR(x_thrust, 102.90, 0.01);
  const double theta = m.eta()[4];
  // Steady, q = r = v = 0: the Coriolis terms on X vanish, so thrust - (W - B) sin(theta) =
  // 13.7 u + 141 u^2 (Fossen's g(eta)_X = (W - B) sin(theta)).
  const double u = root(x_thrust - (p.weight_n - p.buoyancy_n) * std::sin(theta), 13.7, 141.0);
  std::printf("bluerov2 full forward: u %.4f m/s (damping root %.4f), pitch %.1f deg, w %.4f\n",
              m.nu()[0], u, rad_to_deg(theta), m.nu()[2]);
  EXPECT_NEAR(m.nu()[0], u, 1e-4);
  EXPECT_NEAR(m.nu()[0], 0.81, 0.01);  // m/s, about 1.6 kn, with the 12 V thrust limits
  EXPECT_GT(theta, 0.0);               // thrust 8.5 cm below the CG, drag 4.25 cm below: nose up
  EXPECT_LT(theta, deg_to_rad(25));
  EXPECT_LT(std::abs(m.nu()[1]), 1e-6);
  EXPECT_LT(std::abs(m.nu()[5]), 1e-6);
  EXPECT_LT(std::abs(m.eta()[3]), 1e-6);
}

}  // namespace
}  // namespace tiller::sim
