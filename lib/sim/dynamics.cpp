#include "sim/dynamics.hpp"

#include <cmath>

#include "core/config.hpp"
#include "vehicle/thrust_curve.hpp"

namespace tiller::sim {

Matrix6 rigid_body_mass_matrix(double mass, const Vector3& inertia_cg, const Vector3& r_g) {
  // H(r_g)^T diag(m I, I_g) H(r_g), H = [[I, S(r_g)^T], [0, I]].
  const Matrix3 s = skew(r_g);
  Matrix6 m = Matrix6::Zero();
  m.topLeftCorner<3, 3>() = mass * Matrix3::Identity();
  m.topRightCorner<3, 3>() = -mass * s;
  m.bottomLeftCorner<3, 3>() = mass * s;
  m.bottomRightCorner<3, 3>() = Matrix3(inertia_cg.asDiagonal()) - mass * s * s;
  return m;
}

namespace {

Vector3 vec3(const config::Value& v, std::string_view key, config::Range r = {}) {
  const auto n = v.numbers(key, 3, r);
  return {n[0], n[1], n[2]};
}

Vector6 vec6(const config::Value& v, std::string_view key, config::Range r = {}) {
  const auto n = v.numbers(key, 6, r);
  Vector6 out;
  for (int i = 0; i < 6; ++i) out[i] = n[static_cast<std::size_t>(i)];
  return out;
}

void check_positive_definite(const config::Value& where, const Matrix6& m) {
  if (!m.isApprox(m.transpose(), 1e-12)) where.fail("a symmetric mass matrix");
  Eigen::LLT<Matrix6> llt(m);
  if (llt.info() != Eigen::Success) where.fail("a positive-definite mass matrix");
}

}  // namespace

DynamicsParams load_dynamics(const config::Value& d) {
  DynamicsParams p;
  const auto kind = d.choice("model", {"surface_3dof", "underwater_6dof"});
  p.kind = kind == "surface_3dof" ? ModelKind::kSurface3Dof : ModelKind::kUnderwater6Dof;
  p.source = d.string_or("source", "");
  p.thruster_time_constant_s = d.number("thruster_time_constant_s", {0.0, 10.0});
  p.water_density_kg_m3 = d.number_or("water_density_kg_m3", 1025.0, {900.0, 1100.0});
  p.gravity_m_s2 = d.number_or("gravity_m_s2", 9.81, {9.7, 9.9});
  if (auto c = d.find("simulator_thrust_curve")) {
    const std::string name = c->as_string();
    std::string names;
    bool known = false;
    for (const auto& n : ThrustCurve::preset_names()) {
      names += (names.empty() ? "" : ", ") + n;
      known = known || n == name;
    }
    if (!known) c->fail("a thrust curve preset name (" + names + "), got '" + name + "'");
    p.simulator_thrust_curve = name;
  }
  const config::Range nonneg = config::Range::at_least(0.0);

  if (p.kind == ModelKind::kSurface3Dof) {
    // [u v r] -> indices 0, 1, 5 of the 6-DOF vectors.
    constexpr int idx[3] = {0, 1, 5};
    const auto rows = d.at("mass_matrix");
    if (!rows.is_sequence() || rows.size() != 3) rows.fail("3 rows of 3 numbers ([u v r])");
    for (int i = 0; i < 3; ++i) {
      const auto row = rows[static_cast<std::size_t>(i)].as_numbers(3);
      for (int j = 0; j < 3; ++j) p.mass_matrix(idx[i], idx[j]) = row[static_cast<std::size_t>(j)];
    }
    check_positive_definite(rows, p.mass_matrix);
    p.coriolis_mass_matrix = p.mass_matrix;
    if (auto cm = d.find("coriolis_mass_matrix")) {
      if (!cm->is_sequence() || cm->size() != 3) cm->fail("3 rows of 3 numbers ([u v r])");
      for (int i = 0; i < 3; ++i) {
        const auto row = (*cm)[static_cast<std::size_t>(i)].as_numbers(3);
        for (int j = 0; j < 3; ++j)
          p.coriolis_mass_matrix(idx[i], idx[j]) = row[static_cast<std::size_t>(j)];
      }
      if (!p.coriolis_mass_matrix.isApprox(p.coriolis_mass_matrix.transpose(), 1e-12))
        cm->fail("a symmetric matrix");
    }
    const auto lin = d.numbers("linear_damping", 3, nonneg);
    const auto quad = d.numbers("quadratic_damping", 3, nonneg);
    for (int i = 0; i < 3; ++i) {
      p.linear_damping[idx[i]] = lin[static_cast<std::size_t>(i)];
      p.quadratic_damping[idx[i]] = quad[static_cast<std::size_t>(i)];
    }
    if (auto cf = d.find("cross_flow_drag")) {
      p.cross_flow.enabled = true;
      p.cross_flow.length_m = cf->number("length_m", config::Range::positive());
      p.cross_flow.draft_m = cf->number("draft_m", config::Range::positive());
      p.cross_flow.cd = cf->number("cd", {0.0, 5.0});
      p.cross_flow.strips = static_cast<int>(cf->integer_or("strips", 20, 2, 200));
    }
    if (d.has("wind_coefficients")) p.wind_coefficients = vec3(d, "wind_coefficients", nonneg);
    p.mass_kg = p.mass_matrix(0, 0);
  } else {
    p.mass_kg = d.number("mass_kg", config::Range::positive());
    const Vector3 inertia = vec3(d, "inertia_kg_m2", config::Range::positive());
    p.center_of_gravity_m = vec3(d, "center_of_gravity_m", {-10.0, 10.0});
    p.center_of_buoyancy_m = vec3(d, "center_of_buoyancy_m", {-10.0, 10.0});
    const double volume = d.number("displaced_volume_m3", config::Range::positive());
    const Vector6 added = vec6(d, "added_mass", nonneg);
    p.linear_damping = vec6(d, "linear_damping", nonneg);
    p.quadratic_damping = vec6(d, "quadratic_damping", nonneg);
    if (d.has("damping_center_m")) p.damping_center_m = vec3(d, "damping_center_m", {-10.0, 10.0});
    p.weight_n = p.mass_kg * p.gravity_m_s2;
    p.buoyancy_n = p.water_density_kg_m3 * p.gravity_m_s2 * volume;
    p.mass_matrix = rigid_body_mass_matrix(p.mass_kg, inertia, p.center_of_gravity_m);
    p.mass_matrix.diagonal() += added;
    p.coriolis_mass_matrix = p.mass_matrix;
    check_positive_definite(d.at("inertia_kg_m2"), p.mass_matrix);
  }
  return p;
}

}  // namespace tiller::sim
