#include "tune/propose.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/config.hpp"
#include "sim/sim_node.hpp"
#include "tune/text_edit.hpp"

namespace tiller::tune {

std::array<AxisTruth, kAxes> model_axes(const sim::DynamicsParams& d) {
  std::array<AxisTruth, kAxes> t{};
  for (int x = 0; x < kAxes; ++x) {
    const int i = kNuIndex[x];
    auto& a = t[static_cast<std::size_t>(x)];
    a.mass = d.mass_matrix(i, i);
    a.linear = d.linear_damping[i];
    a.quadratic = d.quadratic_damping[i];
  }
  auto& yaw = t[kYaw];
  yaw.mass -= d.mass_matrix(1, 5) * d.mass_matrix(1, 5) / d.mass_matrix(1, 1);
  if (d.cross_flow.enabled) {  // sum over strips of k |x|^3 (vessel_model.cpp's strips, v = 0)
    const auto& cf = d.cross_flow;
    const double dx = cf.length_m / cf.strips;
    const double k = 0.5 * d.water_density_kg_m3 * cf.draft_m * cf.cd * dx;
    for (int s = 0; s < cf.strips; ++s) {
      const double x = -0.5 * cf.length_m + (s + 0.5) * dx;
      yaw.quadratic += k * std::fabs(x) * x * x;
    }
  }
  t[kHeave].bias = d.weight_n - d.buoyancy_n;
  return t;
}

std::string Proposal::diff() const {
  return unified_diff(vehicle.path, vehicle.before, vehicle.after) +
         unified_diff(control.path, control.before, control.after) +
         unified_diff(guidance.path, guidance.before, guidance.after);
}

namespace {

ConfigFile read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read");
  std::stringstream ss;
  ss << in.rdbuf();
  ConfigFile f;
  // As the diff names it: relative to the current directory (the repository), so that
  // `git apply DIR/tune.diff` finds it.
  f.path = std::filesystem::proximate(path).string();
  f.before = split_lines(ss.str());
  f.after = f.before;
  return f;
}

// Steady yaw rate at torque n: d r + d2 r^2 = n.
double steady_rate(double d, double d2, double n) {
  if (d2 <= 1e-12) return d > 0 ? n / d : 0.0;
  return (-d + std::sqrt(d * d + 4 * d2 * n)) / (2 * d2);
}

std::string numbers_text(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + format_number(v[i]);
  return s + "]";
}

}  // namespace

Proposal propose(const Identified& id, const std::string& vehicle_file,
                 const std::string& control_file, const std::string& guidance_file) {
  Proposal p;
  p.vehicle = read(vehicle_file);
  p.control = read(control_file);
  p.guidance = read(guidance_file);
  const sim::DynamicsParams ref_dyn = load_sim_vehicle_file(vehicle_file).dynamics;
  const bool surface = ref_dyn.kind == sim::ModelKind::kSurface3Dof;
  const auto ref = model_axes(ref_dyn);
  // The identified model where there is one, else the reference's.
  std::array<AxisTruth, kAxes> now = ref;
  for (int x = 0; x < kAxes; ++x) {
    const auto& a = id.axis[static_cast<std::size_t>(x)];
    if (!a.identified) continue;
    auto& n = now[static_cast<std::size_t>(x)];
    n.mass = a.mass.value;
    n.linear = std::max(a.linear.value, 0.0);
    n.quadratic = std::max(a.quadratic.value, 0.0);
  }
  const auto note = [&](const std::string& file, const std::string& key, double from, double to) {
    if (format_number(from) != format_number(to)) p.changes.push_back({file, key, from, to});
  };
  const auto change = [&](ConfigFile& f, const std::vector<std::string>& path,
                          const std::string& flow_key, double from, double to) {
    set_value(f.after, path, format_number(to), flow_key);
    std::string key;
    for (const auto& k : path) key += (key.empty() ? "" : ".") + k;
    if (!flow_key.empty()) key += "." + flow_key;
    note(f.path, key, from, to);
  };

  // Vehicle file: the identified axes' mass, damping; the thruster time constant.
  const auto vroot = config::Value::load_file(vehicle_file);
  const auto dyn = vroot.at("dynamics");
  if (surface) {
    const int row[kAxes] = {0, 1, -1, 2};  // the file's [u v r] rows
    auto mm = dyn.at("mass_matrix");
    std::vector<std::vector<double>> m(3);
    for (std::size_t r = 0; r < 3; ++r) m[r] = mm[r].as_numbers(3);
    auto lin = dyn.numbers("linear_damping", 3), quad = dyn.numbers("quadratic_damping", 3);
    for (int x = 0; x < kAxes; ++x) {
      if (row[x] < 0 || !id.axis[static_cast<std::size_t>(x)].identified) continue;
      const auto r = static_cast<std::size_t>(row[x]);
      const auto& n = now[static_cast<std::size_t>(x)];
      const double from = m[r][r];
      m[r][r] = n.mass + (x == kYaw ? m[1][2] * m[1][2] / m[1][1] : 0.0);
      const double cross_flow =
          ref[static_cast<std::size_t>(x)].quadratic - ref_dyn.quadratic_damping[kNuIndex[x]];
      note(vehicle_file, std::string("dynamics.mass_matrix[") + kAxisName[x] + "]", from, m[r][r]);
      note(vehicle_file, std::string("dynamics.linear_damping[") + kAxisName[x] + "]", lin[r],
           n.linear);
      note(vehicle_file, std::string("dynamics.quadratic_damping[") + kAxisName[x] + "]", quad[r],
           std::max(0.0, n.quadratic - cross_flow));
      lin[r] = n.linear;
      // The file's quadratic term is the hull's own: the cross-flow drag (yaw) comes on top.
      quad[r] = std::max(0.0, n.quadratic - cross_flow);
    }
    std::string mt = "[";
    for (std::size_t r = 0; r < 3; ++r) mt += (r ? ", " : "") + numbers_text(m[r]);
    set_value(p.vehicle.after, {"dynamics", "mass_matrix"}, mt + "]");
    set_value(p.vehicle.after, {"dynamics", "linear_damping"}, numbers_text(lin));
    set_value(p.vehicle.after, {"dynamics", "quadratic_damping"}, numbers_text(quad));
  }
  if (id.time_constant > 0)
    change(p.vehicle, {"dynamics", "thruster_time_constant_s"}, "",
           dyn.number("thruster_time_constant_s"), id.time_constant);

  // Velocity PID and station keeping.
  const auto croot = config::Value::load_file(control_file);
  const auto vp = croot.at("velocity_pid");
  const struct {
    const char* key;
    int axis;
  } vaxes[] = {{"surge", kSurge}, {"sway", kSway}, {"yaw", kYaw}};
  for (const auto& va : vaxes) {
    const auto& a = id.axis[static_cast<std::size_t>(va.axis)];
    if (!a.identified || !vp.has(va.key)) continue;
    const auto g = vp.at(va.key);
    const auto& n = now[static_cast<std::size_t>(va.axis)];
    const auto& r = ref[static_cast<std::size_t>(va.axis)];
    const std::vector<std::string> path = {"velocity_pid", va.key};
    change(p.control, path, "k_drag", g.number("k_drag"), n.linear);
    change(p.control, path, "k_drag_quad", g.number("k_drag_quad"), n.quadratic);
    change(p.control, path, "k_error", g.number("k_error"), g.number("k_error") * n.mass / r.mass);
    change(p.control, path, "ki", g.number("ki"), g.number("ki") * n.mass / r.mass);
    if (r.linear > 0)
      change(p.control, path, "i_limit", g.number("i_limit"),
             g.number("i_limit") * n.linear / r.linear);
  }
  if (croot.has("station_keep")) {
    const auto sk = croot.at("station_keep");
    const bool sway = id.axis[kSway].identified;
    const struct {
      const char* key;
      int axis;
    } saxes[] = {{"x", kSurge}, {"y", sway ? kSway : kSurge}, {"yaw", kYaw}};
    for (const auto& sa : saxes) {
      if (!id.axis[static_cast<std::size_t>(sa.axis)].identified || !sk.has(sa.key)) continue;
      const auto g = sk.at(sa.key);
      const auto& n = now[static_cast<std::size_t>(sa.axis)];
      const auto& r = ref[static_cast<std::size_t>(sa.axis)];
      const double s = n.mass / r.mass;
      const std::vector<std::string> path = {"station_keep", sa.key};
      change(p.control, path, "kp", g.number("kp"), g.number("kp") * s);
      change(p.control, path, "ki", g.number("ki"), g.number("ki") * s);
      change(p.control, path, "kd", g.number("kd"),
             std::max(0.0, (g.number("kd") + r.linear) * s - n.linear));
      if (r.linear > 0)
        change(p.control, path, "i_limit", g.number("i_limit"),
               g.number("i_limit") * n.linear / r.linear);
    }
  }

  // Guidance: the turn rates follow the boat's steady turn.
  if (id.axis[kYaw].identified && vp.has("yaw")) {
    const double torque = vp.at("yaw").number("max_output");
    p.r_max_ref = steady_rate(ref[kYaw].linear, ref[kYaw].quadratic, torque);
    p.r_max = steady_rate(now[kYaw].linear, now[kYaw].quadratic, torque);
    const auto groot = config::Value::load_file(guidance_file);
    const auto fo = groot.at("follower");
    const double v = fo.number("turn_rate");
    if (v > 0 && p.r_max_ref > 0)
      change(p.guidance, {"follower", "turn_rate"}, "", v, v * p.r_max / p.r_max_ref);
  }
  return p;
}

void write_proposal(const Proposal& p, const std::string& dir) {
  namespace fs = std::filesystem;
  const auto write = [](const fs::path& f, const std::string& text) {
    fs::create_directories(f.parent_path());
    std::ofstream out(f);
    out << text;
    if (!out) throw std::runtime_error(f.string() + ": cannot write");
  };
  for (const ConfigFile* f : {&p.vehicle, &p.control, &p.guidance}) {
    const fs::path rel = fs::path("config") / fs::path(f->path).parent_path().filename() /
                         fs::path(f->path).filename();
    write(fs::path(dir) / rel, join_lines(f->after));
  }
  write(fs::path(dir) / "tune.diff", p.diff());
}

}  // namespace tiller::tune
