#include "mission/polygon_path.hpp"

#include <cmath>
#include <limits>
#include <queue>

#include "mission/fence.hpp"

namespace tiller::mission {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double cross(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

// Segments p1-p2 and q1-q2 cross at a point inside both (touching at an end does not count).
bool crosses(const MissionPoint& p1, const MissionPoint& p2, const MissionPoint& q1,
             const MissionPoint& q2) {
  const double d1 =
      cross(p2.north - p1.north, p2.east - p1.east, q1.north - p1.north, q1.east - p1.east);
  const double d2 =
      cross(p2.north - p1.north, p2.east - p1.east, q2.north - p1.north, q2.east - p1.east);
  const double d3 =
      cross(q2.north - q1.north, q2.east - q1.east, p1.north - q1.north, p1.east - q1.east);
  const double d4 =
      cross(q2.north - q1.north, q2.east - q1.east, p2.north - q1.north, p2.east - q1.east);
  constexpr double kEps = 1e-9;
  return ((d1 > kEps && d2 < -kEps) || (d1 < -kEps && d2 > kEps)) &&
         ((d3 > kEps && d4 < -kEps) || (d3 < -kEps && d4 > kEps));
}

double dist(const MissionPoint& a, const MissionPoint& b) {
  return std::hypot(a.north - b.north, a.east - b.east);
}

}  // namespace

PolygonPaths::PolygonPaths(const std::vector<MissionPoint>& polygon, double clearance_m)
    : poly_(polygon) {
  FenceShape shape;
  shape.polygon = polygon;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const auto& v = polygon[i];
    const auto& prev = polygon[(i + n - 1) % n];
    const auto& next = polygon[(i + 1) % n];
    const double lu = dist(prev, v), lw = dist(next, v);
    if (lu < 1e-9 || lw < 1e-9) continue;
    double bn = (prev.north - v.north) / lu + (next.north - v.north) / lw;
    double be = (prev.east - v.east) / lu + (next.east - v.east) / lw;
    const double lb = std::hypot(bn, be);
    if (lb < 1e-9) continue;  // a straight vertex: never a corner of a shortest path
    bn /= lb;
    be /= lb;
    for (const double sign : {1.0, -1.0}) {
      MissionPoint c = v;
      c.north += sign * clearance_m * bn;
      c.east += sign * clearance_m * be;
      if (inside(shape, c.north, c.east)) {
        corners_.push_back(c);
        break;
      }
    }
  }
  const std::size_t m = corners_.size();
  dist_.assign(m, std::vector<double>(m, kInf));
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = i + 1; j < m; ++j)
      if (visible(corners_[i], corners_[j]))
        dist_[i][j] = dist_[j][i] = dist(corners_[i], corners_[j]);
}

bool PolygonPaths::visible(const MissionPoint& a, const MissionPoint& b) const {
  const std::size_t n = poly_.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
    if (crosses(a, b, poly_[j], poly_[i])) return false;
  FenceShape shape;
  shape.polygon = poly_;
  // Interior samples: a segment from a boundary point along the boundary, or through a vertex
  // into the outside, crosses no edge properly but has outside points.
  constexpr int kSamples = 16;
  for (int k = 1; k < kSamples; ++k) {
    const double t = static_cast<double>(k) / kSamples;
    if (!inside(shape, a.north + t * (b.north - a.north), a.east + t * (b.east - a.east)))
      return false;
  }
  return true;
}

std::vector<MissionPoint> PolygonPaths::via(const MissionPoint& a, const MissionPoint& b,
                                            double* length) const {
  if (visible(a, b)) {
    if (length) *length = dist(a, b);
    return {};
  }
  // Nodes: the corners 0..m-1, a = m, b = m + 1.
  const std::size_t m = corners_.size();
  std::vector<double> to_a(m), to_b(m);
  for (std::size_t i = 0; i < m; ++i) {
    to_a[i] = visible(a, corners_[i]) ? dist(a, corners_[i]) : kInf;
    to_b[i] = visible(corners_[i], b) ? dist(corners_[i], b) : kInf;
  }
  std::vector<double> d(m, kInf);
  std::vector<std::size_t> from(m, m);  // m: reached from a
  std::vector<bool> done(m, false);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
  for (std::size_t i = 0; i < m; ++i)
    if (to_a[i] < kInf) {
      d[i] = to_a[i];
      q.push({d[i], i});
    }
  while (!q.empty()) {
    const auto [di, i] = q.top();
    q.pop();
    if (done[i]) continue;
    done[i] = true;
    for (std::size_t j = 0; j < m; ++j)
      if (!done[j] && di + dist_[i][j] < d[j]) {
        d[j] = di + dist_[i][j];
        from[j] = i;
        q.push({d[j], j});
      }
  }
  double best = kInf;
  std::size_t last = m;
  for (std::size_t i = 0; i < m; ++i)
    if (d[i] + to_b[i] < best) best = d[i] + to_b[i], last = i;
  if (length) *length = best;
  std::vector<MissionPoint> out;
  if (last == m) return out;
  for (std::size_t i = last; i != m; i = from[i]) out.insert(out.begin(), corners_[i]);
  return out;
}

}  // namespace tiller::mission
