#include "mission/fence.hpp"

#include <cmath>
#include <cstdio>

#include "core/config.hpp"

namespace tiller::mission {

bool inside(const FenceShape& s, double n, double e) {
  if (s.circle) return std::hypot(n - s.centre.north, e - s.centre.east) <= s.radius_m;
  // Crossing number (even-odd) in the north-east plane; an edge point counts as inside.
  bool in = false;
  const auto& p = s.polygon;
  for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    const double ni = p[i].north, ei = p[i].east, nj = p[j].north, ej = p[j].east;
    const double cross = (nj - ni) * (e - ei) - (ej - ei) * (n - ni);
    if (std::fabs(cross) < 1e-9 && std::min(ni, nj) - 1e-9 <= n && n <= std::max(ni, nj) + 1e-9 &&
        std::min(ei, ej) - 1e-9 <= e && e <= std::max(ei, ej) + 1e-9)
      return true;
    if ((ni > n) != (nj > n) && e < (ej - ei) * (n - ni) / (nj - ni) + ei) in = !in;
  }
  return in;
}

int fence_breach(const std::vector<FenceShape>& fence, double n, double e) {
  for (std::size_t k = 0; k < fence.size(); ++k)
    if (inside(fence[k], n, e) != fence[k].inclusion) return static_cast<int>(k);
  return -1;
}

std::string describe_shape(const std::vector<FenceShape>& fence, int k) {
  int same = 0;  // the shape's number among those of its kind
  for (int j = 0; j < k; ++j)
    same += fence[j].circle == fence[k].circle && fence[j].inclusion == fence[k].inclusion;
  return std::string(fence[k].inclusion ? "inclusion " : "exclusion ") +
         (fence[k].circle ? "circle " : "polygon ") + std::to_string(same);
}

void check_items(const Mission& m, const std::string& file) {
  for (std::size_t k = 0; k < m.fence.size(); ++k) {
    const auto& s = m.fence[k];
    if (s.circle ? !(s.radius_m > 0) : s.polygon.size() < 3)
      throw config::Error(file + ": fence " + describe_shape(m.fence, static_cast<int>(k)) +
                          (s.circle ? ": expected a radius > 0 m" : ": expected >= 3 vertices"));
  }
  const auto where = [&](const Item& it) {
    return file + ": item " + std::to_string(it.index) +
           (it.command ? " (command " + std::to_string(it.command) + ")" : std::string());
  };
  for (std::size_t k = 0; k < m.items.size(); ++k) {
    const Item& it = m.items[k];
    if (it.has_point) {
      const int b = fence_breach(m.fence, it.point.north, it.point.east);
      if (b >= 0) {
        char at[64];
        std::snprintf(at, sizeof at, " (%.1f m north, %.1f m east)", it.point.north, it.point.east);
        throw config::Error(where(it) + ": the point" + at + " is " +
                            (m.fence[b].inclusion ? "outside" : "inside") + " the fence (" +
                            describe_shape(m.fence, b) + ")");
      }
    }
    if (it.kind != ItemKind::kJump) continue;
    if (it.jump_to < 0 || it.jump_to >= static_cast<int>(m.items.size()))
      throw config::Error(where(it) + ": jump to an item that is not in the mission");
    bool point = false;  // a jump back must pass a point, or it loops on the spot
    for (int j = std::min<int>(it.jump_to, static_cast<int>(k));
         j <= std::max<int>(it.jump_to, static_cast<int>(k)); ++j)
      point |= m.items[j].has_point;
    if (!point) throw config::Error(where(it) + ": the jump passes no point (an endless loop)");
  }
}

}  // namespace tiller::mission
