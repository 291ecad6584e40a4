#include "vehicle/vehicle.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

namespace tiller {

int axis_index(const std::string& name) {
  for (int i = 0; i < 6; ++i)
    if (name == kAxisNames[static_cast<std::size_t>(i)]) return i;
  return -1;
}

const char* strategy_name(Strategy s) {
  switch (s) {
    case Strategy::kDirectionPreserving:
      return "direction_preserving";
    case Strategy::kPrioritised:
      return "prioritised";
    case Strategy::kClip:
      return "clip";
  }
  return "?";
}

Eigen::Matrix<double, 6, 1> Thruster::wrench_per_newton() const {
  Eigen::Matrix<double, 6, 1> c;
  c.head<3>() = direction;
  c.tail<3>() = position.cross(direction);
  return c;
}

int Vehicle::index_of(const std::string& thruster_name) const {
  for (int i = 0; i < size(); ++i)
    if (thrusters[static_cast<std::size_t>(i)].name == thruster_name) return i;
  return -1;
}

Eigen::MatrixXd Vehicle::effectiveness() const {
  Eigen::MatrixXd b(6, size());
  for (int i = 0; i < size(); ++i)
    b.col(i) = thrusters[static_cast<std::size_t>(i)].wrench_per_newton();
  return b;
}

Eigen::Matrix<double, 4, 3> x_drive_table(double k) {
  Eigen::Matrix<double, 4, 3> m;
  m << 1, 1, 1,   // LF
      1, -1, -1,  // RF
      1, -k, 1,   // LR
      1, k, -1;   // RR
  return m;
}

namespace {

ThrustCurve load_curve(const config::Value& v) {
  try {
    if (v.is_scalar()) return ThrustCurve::preset(v.as_string());
    if (!v.is_map() || v.keys().size() != 1)
      v.fail(
          "a preset name (t200_12v, t200_14v8, t200_16v, t200, t200_poly) or a map with one of "
          "linear, quadratic, "
          "table, polynomial");
    const std::string kind = v.keys().front();
    const config::Value p = v.at(kind);
    if (kind == "linear")
      return ThrustCurve::linear(p.number("forward_n", config::Range::positive()),
                                 p.number("reverse_n", config::Range::positive()));
    if (kind == "quadratic")
      return ThrustCurve::quadratic(p.number("forward_n", config::Range::positive()),
                                    p.number("reverse_n", config::Range::positive()));
    if (kind == "table")
      return ThrustCurve::table(p.numbers("command", 0, {-1.0, 1.0}), p.numbers("thrust_n", 0));
    if (kind == "polynomial") return ThrustCurve::polynomial(p.numbers("coefficients", 0));
    v.fail("one of linear, quadratic, table, polynomial (got '" + kind + "')");
  } catch (const std::invalid_argument& e) {
    v.fail(std::string("a valid thrust curve: ") + e.what());
  }
}

Eigen::Vector3d vec3(const config::Value& v, const char* key) {
  const auto n = v.numbers(key, 3);
  return {n[0], n[1], n[2]};
}

Thruster load_thruster(const config::Value& t) {
  Thruster th;
  th.name = t.string("name");
  if (th.name.empty()) t.at("name").fail("a non-empty thruster name");
  th.position = vec3(t, "position");
  if (th.position.norm() > 100) t.at("position").fail("a position within 100 m of the CG");
  const Eigen::Vector3d d = vec3(t, "direction");
  if (std::abs(d.norm() - 1.0) > 1e-3)
    t.at("direction").fail("a unit vector (length 1 within 1e-3)");
  th.direction = d.normalized();
  th.curve = load_curve(t.at("curve"));
  th.max_forward_n = t.number("max_forward_n", config::Range::positive());
  th.max_reverse_n = t.number("max_reverse_n", config::Range::positive());
  if (th.max_forward_n > th.curve.max_forward_n() * (1 + 1e-6)) {
    std::ostringstream os;
    os << "at most the curve's forward thrust " << th.curve.max_forward_n() << " N";
    t.at("max_forward_n").fail(os.str());
  }
  if (th.max_reverse_n > th.curve.max_reverse_n() * (1 + 1e-6)) {
    std::ostringstream os;
    os << "at most the curve's reverse thrust " << th.curve.max_reverse_n() << " N";
    t.at("max_reverse_n").fail(os.str());
  }
  th.group = t.string("group");
  th.reversed = t.boolean("reversed");
  return th;
}

std::vector<int> load_axes(const config::Value& v) {
  std::vector<int> out;
  for (const auto& item : v.items()) {
    const int a = axis_index(item.as_string());
    if (a < 0) item.fail("an axis name: X, Y, Z, K, M or N");
    for (int seen : out)
      if (seen == a) item.fail("each axis once");
    out.push_back(a);
  }
  return out;
}

AllocationSpec load_allocation(const config::Value& a, const Vehicle& v) {
  AllocationSpec s;
  const std::string strat = a.choice("strategy", {"direction_preserving", "prioritised", "clip"});
  s.strategy = strat == "prioritised" ? Strategy::kPrioritised
               : strat == "clip"      ? Strategy::kClip
                                      : Strategy::kDirectionPreserving;
  if (auto p = a.find("priority")) {
    if (s.strategy != Strategy::kPrioritised) p->fail("no priority unless strategy is prioritised");
    std::set<int> seen;
    for (const auto& level : p->items()) {
      std::vector<int> axes;
      if (level.is_sequence()) {
        axes = load_axes(level);
      } else {
        const int ax = axis_index(level.as_string());
        if (ax < 0) level.fail("an axis name (X, Y, Z, K, M, N) or a list of them");
        axes.push_back(ax);
      }
      for (int ax : axes)
        if (!seen.insert(ax).second) level.fail("each axis at most once in priority");
      s.priority.push_back(axes);
    }
    for (int ax = 0; ax < 6; ++ax)
      if (!seen.count(ax)) s.priority.push_back({ax});
  } else if (s.strategy == Strategy::kPrioritised) {
    a.fail("a `priority` list of axes for strategy prioritised");
  }
  if (auto m = a.find("mixing")) {
    if (s.strategy == Strategy::kPrioritised)
      m->fail("no mixing matrix with strategy prioritised (it needs the geometry)");
    const int n = v.size();
    s.matrix_commands = m->choice("units", {"thrust_fraction", "command"}) == "command";
    s.normalise_always = m->choice("normalise", {"above_one", "always"}) == "always";
    if (m->find("x_drive") && m->find("rows"))
      m->at("rows").fail("either x_drive or axes + rows, not both");
    if (auto x = m->find("x_drive")) {
      s.matrix_key = "x_drive";
      const double k = x->number("rear_strafe_reduction", {0.0, 2.0});
      const auto names = x->at("thrusters");
      if (names.size() != 4 || n != 4)
        names.fail("the 4 thruster names in order [LF, RF, LR, RR] (vehicle with 4 thrusters)");
      s.matrix_axes = {0, 1, 5};
      s.matrix = Eigen::MatrixXd::Zero(n, 3);
      const auto table = x_drive_table(k);
      std::set<int> used;
      for (int r = 0; r < 4; ++r) {
        const auto& name = names[static_cast<std::size_t>(r)];
        const int idx = v.index_of(name.as_string());
        if (idx < 0) name.fail("a thruster name of this vehicle");
        if (!used.insert(idx).second)
          name.fail("each of the vehicle's 4 thrusters once ('" + name.as_string() +
                    "' is repeated)");
        s.matrix.row(idx) = table.row(r);
      }
    } else {
      s.matrix_key = "rows";
      s.matrix_axes = load_axes(m->at("axes"));
      if (s.matrix_axes.empty()) m->at("axes").fail("at least one axis");
      const auto rows = m->at("rows");
      s.matrix = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(s.matrix_axes.size()));
      std::set<int> filled;
      if (!rows.is_map()) rows.fail("a map from thruster name to a row of numbers");
      for (const auto& key : rows.keys()) {
        const int idx = v.index_of(key);
        if (idx < 0)
          rows.at(key).fail("a row named after a thruster of this vehicle ('" + key +
                            "' is not one)");
        const auto r = rows.numbers(key, s.matrix_axes.size(), {-100.0, 100.0});
        for (std::size_t j = 0; j < r.size(); ++j)
          s.matrix(idx, static_cast<Eigen::Index>(j)) = r[j];
        filled.insert(idx);
      }
      for (int i = 0; i < n; ++i)
        if (!filled.count(i))
          rows.fail("one row per thruster (missing: " +
                    v.thrusters[static_cast<std::size_t>(i)].name + ")");
    }
  }
  return s;
}

}  // namespace

Vehicle load_vehicle(const config::Value& root) {
  Vehicle v;
  v.source_file = root.file();
  v.name = root.string("name");
  v.description = root.string_or("description", "");
  const auto ts = root.at("thrusters");
  if (!ts.is_sequence() || ts.size() == 0 || ts.size() > kMaxThrusters)
    ts.fail("a list of 1 to 16 thrusters");
  for (const auto& t : ts.items()) {
    Thruster th = load_thruster(t);
    if (v.index_of(th.name) >= 0) t.at("name").fail("a thruster name used only once");
    v.thrusters.push_back(std::move(th));
  }
  v.allocation = load_allocation(root.at("allocation"), v);
  if (auto d = root.find("dynamics")) d->mark_used();  // lib/sim parses it
  return v;
}

Vehicle load_vehicle_file(const std::string& path) {
  const config::Value root = config::Value::load_file(path);
  Vehicle v = load_vehicle(root);
  root.check_all_used();
  return v;
}

}  // namespace tiller
