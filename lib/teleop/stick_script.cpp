#include "teleop/stick_script.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <tiller/heartbeat_t.hpp>

#include "core/angles.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller {

namespace {

constexpr std::int64_t kAxisMax = 32767;
constexpr std::int32_t kNeeds = int{odometry_t::VALID_DEPTH} | int{odometry_t::VALID_ATTITUDE};

StickStep load_step(const config::Value& s, const StickScriptParams& p) {
  StickStep st;
  st.name = s.string("name");
  if (auto axes = s.find("axes")) {
    if (!axes->is_map()) axes->fail("a map of js axis number to value, e.g. {5: 32767}");
    for (const std::string& k : axes->keys()) {
      int axis = -1;
      try {
        axis = std::stoi(k);
      } catch (...) {
      }
      if (axis < 0 || axis >= p.n_axes || std::to_string(axis) != k)
        axes->at(k).fail("an axis number 0.." + std::to_string(p.n_axes - 1) + " as the key");
      st.axes.emplace_back(axis, static_cast<int>(axes->integer(k, -kAxisMax, kAxisMax)));
    }
  }
  if (auto press = s.find("press")) {
    if (!press->is_sequence()) press->fail("a list of button numbers, e.g. [6]");
    for (const config::Value& b : press->items())
      st.press.push_back(static_cast<int>(b.as_integer(0, p.n_buttons - 1)));
  }
  st.hold = from_seconds(s.number_or("hold_s", 0.0, {0.0, 3600.0}));
  st.timeout = from_seconds(s.number_or("timeout_s", 60.0, config::Range::positive()));
  if (auto u = s.find("until")) {
    const std::vector<std::string> keys = u->keys();
    if (!u->is_map() || keys.size() != 1)
      u->fail("one of {depth_at_least_m: D}, {depth_at_most_m: D}, {turned_deg: A}");
    const std::string& k = keys[0];
    if (k == "depth_at_least_m") {
      st.until = StickStep::Until::depth_at_least;
      st.until_value = u->number(k, {-100.0, 1000.0});
    } else if (k == "depth_at_most_m") {
      st.until = StickStep::Until::depth_at_most;
      st.until_value = u->number(k, {-100.0, 1000.0});
    } else if (k == "turned_deg") {
      st.until = StickStep::Until::turned_at_least;
      st.until_value = u->angle_deg(k, {-3600.0, 3600.0});
    } else {
      u->at(k).fail("depth_at_least_m, depth_at_most_m or turned_deg");
    }
  }
  if (auto m = s.find("measure")) {
    if (m->has("depth_m")) st.depth_m = m->number("depth_m", {-100.0, 1000.0});
    if (m->has("turn_deg")) st.turn_rad = m->angle_deg("turn_deg", {-3600.0, 3600.0});
    if (m->has("depth")) st.depth_held = m->choice("depth", {"held"}) == "held";
    if (m->has("heading")) st.heading_held = m->choice("heading", {"held"}) == "held";
    if (st.depth_held && !std::isnan(st.depth_m)) m->at("depth").fail("depth_m or depth, not both");
    if (st.heading_held && !std::isnan(st.turn_rad))
      m->at("heading").fail("turn_deg or heading, not both");
    if (!st.measured()) m->fail("depth_m or depth: held, and / or turn_deg or heading: held");
    st.settle = from_seconds(m->number_or("settle_s", 0.0, {0.0, 3600.0}));
    st.max_depth_rms_m =
        m->number_or("max_depth_rms_m", st.max_depth_rms_m, config::Range::positive());
    if (m->has("max_heading_rms_deg"))
      st.max_heading_rms_rad = m->angle_deg("max_heading_rms_deg", {0.0, 360.0});
    st.max_depth_m = m->number_or("max_depth_m", st.max_depth_m, config::Range::positive());
    if (m->has("max_heading_deg"))
      st.max_heading_rad = m->angle_deg("max_heading_deg", {0.0, 360.0});
  }
  return st;
}

}  // namespace

StickScriptParams load_stick_script(const config::Value& root) {
  StickScriptParams p;
  p.period = from_hz(root.number_or("rate_hz", 50.0, {1.0, 1000.0}));
  p.n_axes = static_cast<int>(root.integer_or("axes", 6, 1, 64));
  p.n_buttons = static_cast<int>(root.integer_or("buttons", 12, 1, 128));
  p.press = from_seconds(root.number_or("press_s", 0.2, {0.05, 5.0}));
  p.odometry_timeout = from_seconds(root.number_or("odometry_timeout_s", 0.5, {0.05, 10.0}));
  p.start_timeout = from_seconds(root.number_or("start_timeout_s", 20.0, {0.1, 600.0}));
  const config::Value steps = root.at("steps");
  if (!steps.is_sequence() || steps.size() == 0) steps.fail("a non-empty list of steps");
  for (const config::Value& s : steps.items()) p.steps.push_back(load_step(s, p));
  return p;
}

StickScriptParams load_stick_script_file(const std::string& path) {
  const config::Value root = config::Value::load_file(path);
  StickScriptParams p = load_stick_script(root);
  root.check_all_used();
  return p;
}

StickScriptNode::StickScriptNode(StickScriptParams p)
    : Node("stick-script", p.period), p_(std::move(p)), odom_fresh_(p_.odometry_timeout) {
  subscribe(channels::kOdometry, &StickScriptNode::on_odometry);
  rejected_odom_ = &counter("rejected.odometry.invalid");
  invalid_odom_ = &counter("odometry.invalid");
  js_.device = "stick-script";
  js_.connected = true;
  js_.late_inits = 0;
  js_.n_axes = p_.n_axes;
  js_.axes.assign(static_cast<std::size_t>(p_.n_axes), 0);
  js_.n_buttons = p_.n_buttons;
  js_.buttons.assign(static_cast<std::size_t>(p_.n_buttons), false);
  set_health(heartbeat_t::STATE_DEGRADED, "waiting for odometry");
}

void StickScriptNode::on_odometry(const odometry_t& o, TimeUs now) {
  if (!on_time(odom_fresh_, o.utime, now, "odometry")) return;
  if (checks::check(o) != nullptr) {
    reject(*rejected_odom_);
    return;
  }
  // The pilot watches the depth gauge and the compass: odometry without a valid depth and
  // attitude (odometry_t.valid) is not taken, so it goes stale and a step needing it fails.
  if ((o.valid & kNeeds) != kNeeds) {
    ++*invalid_odom_;
    return;
  }
  odom_fresh_.mark(now, o.utime, clock_offset());
  depth_ = o.position[2];
  heading_ = o.orientation[2];
  if (!have_odom_) {
    start_heading_ = last_heading_ = heading_;
    turned_ = 0;
  }
  turned_ += angle_diff(heading_, last_heading_);  // unwrapped, + clockwise
  last_heading_ = heading_;
  have_odom_ = true;
}

void StickScriptNode::set_stick(TimeUs now) {
  if (on_stick_) on_stick_(js_, now);
}

void StickScriptNode::start_step(int i, TimeUs now) {
  step_ = i;
  step_start_ = now;
  sum_d2_ = sum_h2_ = 0;
  if (i >= static_cast<int>(p_.steps.size())) {
    std::fill(js_.axes.begin(), js_.axes.end(), 0);
    std::fill(js_.buttons.begin(), js_.buttons.end(), false);
    done_ = true;  // before the callback, which ends the run on it
    set_stick(now);
    set_health(heartbeat_t::STATE_OK, "script complete" + std::string(failed() ? " (FAILED)" : ""));
    return;
  }
  const StickStep& s = p_.steps[static_cast<std::size_t>(i)];
  std::fill(js_.axes.begin(), js_.axes.end(), 0);
  for (const auto& [axis, value] : s.axes) js_.axes[static_cast<std::size_t>(axis)] = value;
  std::fill(js_.buttons.begin(), js_.buttons.end(), false);
  for (int b : s.press) js_.buttons[static_cast<std::size_t>(b)] = true;
  if (s.measured()) {
    StickMeasure m;
    m.step = s.name;
    m.depth = s.depth_held || !std::isnan(s.depth_m);
    m.heading = s.heading_held || !std::isnan(s.turn_rad);
    m.depth_ref = s.depth_m;
    m.heading_ref = start_heading_ + s.turn_rad;
    measures_.push_back(m);
  }
  std::fprintf(stderr, "tiller-stick-script: step %d/%zu: %s\n", i + 1, p_.steps.size(),
               s.name.c_str());
  set_stick(now);
  set_health(heartbeat_t::STATE_OK, "step " + std::to_string(i + 1) + "/" +
                                        std::to_string(p_.steps.size()) + ": " + s.name);
}

void StickScriptNode::fail(const std::string& why, TimeUs now) {
  why_ = why;
  std::fprintf(stderr, "tiller-stick-script: FAILED: %s\n", why.c_str());
  start_step(static_cast<int>(p_.steps.size()), now);  // centre and stop
}

bool StickScriptNode::condition_met(const StickStep& s) const {
  switch (s.until) {
    case StickStep::Until::time:
      return true;
    case StickStep::Until::depth_at_least:
      return depth_ >= s.until_value;
    case StickStep::Until::depth_at_most:
      return depth_ <= s.until_value;
    case StickStep::Until::turned_at_least:
      return s.until_value >= 0 ? turned_ >= s.until_value : turned_ <= s.until_value;
  }
  return false;
}

void StickScriptNode::on_tick(TimeUs now) {
  if (done_) return;
  if (first_tick_ < 0) first_tick_ = now;
  const bool fresh = odom_fresh_.fresh(now);
  if (step_ < 0) {
    if (have_odom_ && fresh) {
      start_step(0, now);
    } else if (now - first_tick_ > p_.start_timeout) {
      fail("no odometry within " + std::to_string(p_.start_timeout / kUsPerSecond) + " s", now);
    }
    return;
  }
  const StickStep& s = p_.steps[static_cast<std::size_t>(step_)];
  const TimeUs t = now - step_start_;
  if (!s.press.empty() && t >= p_.press &&
      std::any_of(js_.buttons.begin(), js_.buttons.end(), [](bool b) { return b; })) {
    std::fill(js_.buttons.begin(), js_.buttons.end(), false);  // released
    set_stick(now);
  }
  const bool needs_odom = s.until != StickStep::Until::time || s.measured();
  if (needs_odom && !fresh) {
    fail("odometry lost during step '" + s.name + "'", now);
    return;
  }
  if (s.measured() && t >= s.settle) {
    StickMeasure& m = measures_.back();
    if (m.samples == 0) {  // `held`: against what the vehicle has when the measurement begins
      if (s.depth_held) m.depth_ref = depth_;
      if (s.heading_held) m.heading_ref = heading_;
    }
    ++m.samples;
    if (m.depth) {
      const double e = std::abs(depth_ - m.depth_ref);
      sum_d2_ += e * e;
      m.depth_max = std::max(m.depth_max, e);
      m.depth_rms = std::sqrt(sum_d2_ / m.samples);
    }
    if (m.heading) {
      const double e = std::abs(angle_diff(heading_, m.heading_ref));
      sum_h2_ += e * e;
      m.heading_max = std::max(m.heading_max, e);
      m.heading_rms = std::sqrt(sum_h2_ / m.samples);
    }
  }
  if (t >= s.hold && condition_met(s)) {
    if (!measures_.empty() && measures_.back().step == s.name) {
      StickMeasure& m = measures_.back();
      m.passed = m.samples > 0 &&
                 !(m.depth && (m.depth_rms > s.max_depth_rms_m || m.depth_max > s.max_depth_m)) &&
                 !(m.heading &&
                   (m.heading_rms > s.max_heading_rms_rad || m.heading_max > s.max_heading_rad));
      if (!m.passed) why_ = "step '" + s.name + "': error over its limit";
    }
    start_step(step_ + 1, now);
    return;
  }
  if (t >= s.timeout) fail("step '" + s.name + "' not done within its timeout", now);
}

std::string StickScriptNode::report() const {
  std::string out;
  char line[256];
  for (const StickMeasure& m : measures_) {
    if (m.depth) {
      std::snprintf(
          line, sizeof line,
          "%-22s depth error   RMS %.3f m   max %.3f m   (%d samples, against %.3f m)%s\n",
          m.step.c_str(), m.depth_rms, m.depth_max, m.samples, m.depth_ref,
          m.passed ? "" : "  OVER");
      out += line;
    }
    if (m.heading) {
      std::snprintf(
          line, sizeof line,
          "%-22s heading error RMS %.2f deg max %.2f deg (%d samples, against %.1f deg)%s\n",
          m.step.c_str(), rad_to_deg(m.heading_rms), rad_to_deg(m.heading_max), m.samples,
          rad_to_deg(wrap_pi(m.heading_ref)), m.passed ? "" : "  OVER");
      out += line;
    }
  }
  out += failed() ? "verdict: FAILED: " + why_ + "\n" : "verdict: passed\n";
  return out;
}

}  // namespace tiller
