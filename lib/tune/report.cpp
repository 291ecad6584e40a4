#include "tune/report.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

namespace tiller::tune {

namespace {

std::string line(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string line(const char* fmt, ...) {
  char buf[256];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  return std::string(buf) + "\n";
}

double rel(double got, double ref) {
  return ref != 0 ? (got - ref) / std::fabs(ref) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::array<double, kAxes> fastest(const Record& r, const Identified& id) {
  std::array<double, kAxes> top{};
  for (int x = 0; x < kAxes; ++x) {
    if (!id.axis[static_cast<std::size_t>(x)].identified) continue;
    for (const auto& s : r.motion)
      top[static_cast<std::size_t>(x)] = std::max(
          top[static_cast<std::size_t>(x)], std::fabs(s.nu[static_cast<std::size_t>(kNuIndex[x])]));
  }
  return top;
}

Differences differences(const Identified& id, const std::array<AxisTruth, kAxes>& ref,
                        double ref_tc, const std::array<double, kAxes>& top) {
  Differences d;
  for (int x = 0; x < kAxes; ++x) {
    const auto& a = id.axis[static_cast<std::size_t>(x)];
    const auto& t = ref[static_cast<std::size_t>(x)];
    auto& o = d.axis[static_cast<std::size_t>(x)];
    const double v = top[static_cast<std::size_t>(x)];
    o = {rel(a.mass.value, t.mass), rel(a.linear.value, t.linear),
         rel(a.quadratic.value, t.quadratic),
         rel(a.linear.value * v + a.quadratic.value * v * v, t.linear * v + t.quadratic * v * v)};
  }
  d.time_constant = rel(id.time_constant, ref_tc);
  return d;
}

std::string identify_report(const Identified& id, const std::array<AxisTruth, kAxes>& ref,
                            double ref_tc, const std::array<double, kAxes>& top,
                            const std::string& ref_name) {
  const Differences d = differences(id, ref, ref_tc, top);
  std::string s = line("%-8s %-22s %12s %10s %12s %8s", "axis", "parameter", "identified",
                       "+-2 sigma", ref_name.c_str(), "diff");
  const char* units[kAxes][3] = {{"kg", "N s/m", "N s2/m2"},
                                 {"kg", "N s/m", "N s2/m2"},
                                 {"kg", "N s/m", "N s2/m2"},
                                 {"kg m2", "N m s", "N m s2"}};
  for (int x = 0; x < kAxes; ++x) {
    const auto& a = id.axis[static_cast<std::size_t>(x)];
    if (!a.identified) {
      s += line("%-8s not identified: %s", kAxisName[x], a.why.c_str());
      continue;
    }
    const auto& t = ref[static_cast<std::size_t>(x)];
    const Estimate* e[] = {&a.mass, &a.linear, &a.quadratic};
    const double tv[] = {t.mass, t.linear, t.quadratic};
    const char* names[] = {"mass (with added)", "linear damping", "quadratic damping"};
    for (int k = 0; k < 3; ++k) {
      const double r = d.axis[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)];
      char pct[16] = "-";
      if (std::isfinite(r)) std::snprintf(pct, sizeof pct, "%+.1f %%", 100 * r);
      s += line("%-8s %-14s %-7s %12.3f %10.3f %12.3f %8s", k == 0 ? kAxisName[x] : "", names[k],
                units[x][k], e[k]->value, 2 * e[k]->std, tv[k], pct);
    }
    if (x == kHeave)
      s += line("%-8s %-22s %12.3f %10.3f %12.3f", "", "weight - buoyancy N", a.bias.value,
                2 * a.bias.std, t.bias);
    const double v = top[static_cast<std::size_t>(x)];
    s += line(
        "%-8s drag at %.2f (fastest flown): %.1f vs %.1f (%+.1f %%); %d windows, "
        "%.2f %% unexplained",
        "", v, a.linear.value * v + a.quadratic.value * v * v, t.linear * v + t.quadratic * v * v,
        100 * d.axis[static_cast<std::size_t>(x)][3], a.windows, 100 * a.unexplained);
  }
  s += line("thruster time constant %.4f s (95 %%: %.4f..%.4f), %s %.4f s (%+.1f %%)",
            id.time_constant, id.time_constant_low, id.time_constant_high, ref_name.c_str(), ref_tc,
            100 * d.time_constant);
  return s;
}

std::string proposal_report(const Proposal& p) {
  std::string s;
  for (const auto& c : p.changes)
    s += line("%-40s %-42s %10.4g -> %.4g", c.file.c_str(), c.key.c_str(), c.from, c.to);
  if (p.r_max_ref > 0)
    s += line("steady turn at the yaw loop's largest torque: %.3f rad/s (reference %.3f)", p.r_max,
              p.r_max_ref);
  return s;
}

}  // namespace tiller::tune
