#include "nav/nav_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/angles.hpp"
#include "core/message_checks.hpp"
#include "runtime/channels.hpp"

namespace tiller::nav {

namespace {
constexpr double kPositionCap = 1e6;   // m^2: (1 km)^2, an unobserved north / east
constexpr double kVelocityCap = 1e2;   // (m/s)^2: (10 m/s)^2
constexpr double kSurfaceVar = 1e-6;   // m^2 and (m/s)^2: a surface vehicle's d = 0, w = 0
constexpr double kAccelBiasCap = 1e2;  // (m/s^2)^2: an unused accelerometer's biases
constexpr double kGravity = 9.80665;   // m/s^2, standard gravity

double sq(double x) {
  return x * x;
}
// The largest eigenvalue of a symmetric 2x2 [a b; b c].
double largest_eigen(double a, double b, double c) {
  return 0.5 * (a + c) + std::sqrt(0.25 * sq(a - c) + sq(b));
}
// A variance from a message (0 = unknown) or the configured 1-sigma.
double variance_or(double v, double default_std) {
  return v > 0 ? v : sq(default_std);
}
}  // namespace

NavNode::NavNode(const NavParams& p)
    : Node("nav", from_hz(p.rate_hz)),
      p_(p),
      ekf_(p.process),
      gnss_fresh_(from_seconds(std::max(p.gnss.timeout_s, p.gnss.max_latency_s))),
      imu_fresh_(from_seconds(p.imu.timeout_s)),
      heading_fresh_(from_seconds(std::max(p.imu.timeout_s, 1.0))),
      pressure_fresh_(from_seconds(p.depth.timeout_s)),
      dvl_fresh_(from_seconds(std::max(p.dvl.timeout_s, 1.0))),
      dvl_only_(p.dvl.enabled && !p.gnss.enabled) {
  subscribe(channels::kGnss, &NavNode::on_gnss);
  subscribe(channels::kImu, &NavNode::on_imu);
  subscribe(channels::kHeading, &NavNode::on_heading);
  subscribe(channels::kPressure, &NavNode::on_pressure);
  subscribe(channels::kDvl, &NavNode::on_dvl);
  advertise<odometry_t>(channels::kOdometry);
  advertise<datum_t>(channels::kDatum);
  bad_gnss_ = &counter("rejected.gnss.invalid");
  bad_imu_ = &counter("rejected.imu.invalid");
  bad_heading_ = &counter("rejected.heading.invalid");
  bad_pressure_ = &counter("rejected.pressure.invalid");
  gate_gnss_ = &counter("rejected.gnss.gate");
  gate_gnss_velocity_ = &counter("rejected.gnss_velocity.gate");
  gate_heading_ = &counter("rejected.heading.gate");
  gate_depth_ = &counter("rejected.depth.gate");
  gate_sway_ = &counter("rejected.sway.gate");
  fixes_used_ = &counter("gnss.fixes_used");
  repeated_ = &counter("rejected.gnss.repeated");
  no_fix_ = &counter("gnss.no_fix");
  resets_ = &counter("resets");
  too_late_ = &counter("gnss.too_late");
  dr_entered_ = &counter("dead_reckoning.entered");
  invalid_out_ = &counter("odometry.position_invalid");
  datum_restarts_ = &counter("gnss.datum_restarts");
  blended_ = &counter("gnss.blended_corrections");
  heading_other_ignored_ = &counter("heading.other_ignored");
  bad_dvl_ = &counter("rejected.dvl.invalid");
  dvl_no_lock_ = &counter("dvl.no_lock");
  dvl_fom_ = &counter("rejected.dvl.fom");
  gate_dvl_ = &counter("rejected.dvl.gate");
  dvl_used_ = &counter("dvl.used");
  dvl_lost_ = &counter("dvl.lost");
  dvl_status_.reserve(160);

  State x = State::Zero();
  Covariance c = Covariance::Zero();
  c(kN, kN) = c(kE, kE) = kPositionCap;
  c(kD, kD) = p.depth_source == DepthSource::kSurface ? kSurfaceVar : kPositionCap;
  c(kU, kU) = c(kV, kV) = c(kW, kW) = sq(p.initial_velocity_std_mps);
  if (p.depth_source == DepthSource::kSurface) c(kW, kW) = kSurfaceVar;
  c(kPsi, kPsi) = sq(kPi);
  c(kBiasR, kBiasR) = sq(p.initial_gyro_bias_std);
  c(kBiasAx, kBiasAx) = c(kBiasAy, kBiasAy) = sq(p.initial_accel_bias_std);
  c(kCurrentN, kCurrentN) = c(kCurrentE, kCurrentE) = sq(p.initial_current_std_mps);
  ekf_.reset(x, c);
  attitude_var_[0] = attitude_var_[1] = sq(p.imu.default_attitude_std);
  for (double& v : rate_var_) v = sq(p.imu.default_rate_std);
  if (p.fixed_datum) {
    datum_.Reset(p.datum_latitude_deg, p.datum_longitude_deg, p.datum_altitude_m);
    have_datum_ = true;
  }
  odom_.n_pose_cov = 36;
  odom_.pose_covariance.assign(36, 0.0);
  odom_.n_velocity_cov = 36;
  odom_.velocity_covariance.assign(36, 0.0);
  set_health(heartbeat_t::STATE_DEGRADED, "waiting for sensors");
}

void NavNode::advance(TimeUs t) {
  if (!started_) {
    started_ = true;
    t_ = t;
    return;
  }
  if (t <= t_) return;
  // The accelerometer drives the velocity only while the IMU is fresh (a stale sample's
  // acceleration is not integrated on).
  motion_.accel =
      p_.imu.use_acceleration && have_imu_ && t - last_imu_ <= from_seconds(p_.imu.timeout_s);
  // The vertical too, with a pressure depth and a DVL (the accelerometer's vertical bias has no
  // state: the DVL's w and the pressure's depth keep it in check, velocity_vertical its room).
  motion_.accel_vertical =
      motion_.accel && p_.depth_source == DepthSource::kPressure && p_.dvl.enabled;
  ekf_.predict(to_seconds(t - t_), motion_);
  t_ = t;
}

double NavNode::align(TimeUs utime, TimeUs now) {
  const TimeUs tm = std::min(utime, now);
  advance(tm);
  return std::max(0.0, to_seconds(t_ - tm));
}

void NavNode::on_gnss(const gnss_fix_t& m, TimeUs now) {
  if (!on_time(gnss_fresh_, m.utime, now, "gnss")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_gnss_);
    return;
  }
  gnss_fresh_.mark(now, m.utime, clock_offset());
  if (!p_.gnss.enabled) return;
  if (m.fix_type < p_.gnss.min_fix || m.fix_type == gnss_fix_t::FIX_DEAD_RECKONING) {
    ++*no_fix_;
    return;
  }
  // One measurement, fused once: the same epoch again (gnss_utime, the receiver's time of fix)
  // is refused and counted (0: a driver that does not know the time; not compared).
  if (m.gnss_utime != 0 && m.gnss_utime == last_epoch_) {
    reject(*repeated_);
    return;
  }
  last_epoch_ = m.gnss_utime;
  // When the fix was taken: its utime (reception) less the receiver's configured delay.
  const TimeUs taken = std::min(m.utime, now) - from_seconds(p_.gnss.latency_s);
  if (started_ && to_seconds(t_ - taken) > p_.gnss.max_latency_s) {
    ++*too_late_;
    return;
  }
  // The fix's own 1-sigma (floored), else default_std_m: an unknown accuracy is poor, not
  // perfect. An RTK fix without the receiver's statistics is at most its RTK state's 1-sigma.
  const double rtk = m.accuracy_source == gnss_fix_t::ACCURACY_RECEIVER ? 0.0
                     : m.fix_type == gnss_fix_t::FIX_RTK_FIXED          ? p_.gnss.rtk_fixed_std_m
                     : m.fix_type == gnss_fix_t::FIX_RTK_FLOAT          ? p_.gnss.rtk_float_std_m
                                                                        : 0.0;
  auto std_of = [&](double s) {
    if (s <= 0 && rtk <= 0) return p_.gnss.default_std_m;
    const double v = s > 0 ? s : p_.gnss.default_std_m;
    return std::max(rtk > 0 ? std::min(v, rtk) : v, p_.gnss.min_std_m);
  };
  const double sn = std_of(m.position_std[0]), se = std_of(m.position_std[1]);
  if (!have_datum_ && !hold_datum(m, std::max(sn, se), taken)) return;
  const double lag = align(taken, now);
  const bool has_altitude = m.fix_type >= gnss_fix_t::FIX_3D;
  double east = 0, north = 0, up = 0;
  datum_.Forward(m.latitude, m.longitude, has_altitude ? m.altitude : datum_.HeightOrigin(), east,
                 north, up);
  const Motion& mo = motion_;
  const State& x = ekf_.x();
  // The fix is `lag` s older than the filter: move it on with the estimated velocity.
  const Eigen::Vector3d v_ned = Ekf::rotation(mo.roll, mo.pitch, x(kPsi)) * x.segment<3>(kU);
  const Eigen::Vector2d z(north + v_ned(0) * lag, east + v_ned(1) * lag);
  const double n0 = x(kN), e0 = x(kE);  // before this fix: the published one is continuous
  const bool first = !position_init_;   // the first fix sets the position: nothing to blend
  if (!position_init_) {
    ekf_.set_position_ne(z(0), z(1), std::max(sq(sn), sq(se)));
    position_init_ = true;
    last_fix_ = now;
    ++*fixes_used_;
  } else {
    const UpdateResult r =
        ekf_.update_position_ne(z, Eigen::Vector2d(sq(sn), sq(se)).asDiagonal(), p_.gnss.gate_chi2);
    if (r.accepted) {
      gated_in_a_row_ = 0;
      last_fix_ = now;
      ++*fixes_used_;
    } else {
      reject(*gate_gnss_);
      if (++gated_in_a_row_ >= p_.gnss.reset_after) {
        ekf_.set_position_ne(z(0), z(1), std::max(sq(sn), sq(se)));
        gated_in_a_row_ = 0;
        last_fix_ = now;
        ++*resets_;
        blend(n0, e0, std::max(sn, se));
      }
      return;
    }
  }
  if (p_.gnss.use_velocity && m.velocity_valid && heading_init_) fuse_velocity(m, lag);
  // The position's move by this fix, the velocity update's included (the two are correlated).
  if (!first) blend(n0, e0, std::max(sn, se));
}

void NavNode::fuse_velocity(const gnss_fix_t& m, double lag) {
  const Motion& mo = motion_;
  const State& x = ekf_.x();
  // The velocity over ground `lag` s ago, turned on by the heading change since (a body-frame
  // velocity carries the turn).
  const double turned = (mo.r - x(kBiasR)) * lag;
  const Eigen::Vector2d zv(m.speed * std::cos(m.course + turned),
                           m.speed * std::sin(m.course + turned));
  const double vv = sq(p_.gnss.velocity_std_mps);
  const UpdateResult r =
      ekf_.update_velocity_ne(zv, Eigen::Vector2d(vv, vv).asDiagonal(), mo, p_.gnss.gate_chi2);
  if (!r.accepted) reject(*gate_gnss_velocity_);
}

void NavNode::blend(double n0, double e0, double std_m) {
  if (p_.recovery.rate_mps <= 0) return;
  // This fix moved the filter from (n0, e0): up to std_m of that reaches the published position
  // at once, as any fix's correction does; the rest joins the offset that shrinks at rate_mps.
  const double dn = n0 - ekf_.x()(kN), de = e0 - ekf_.x()(kE);
  const double d = std::hypot(dn, de);
  if (d <= std_m) return;
  const double keep = (d - std_m) / d;
  blend_n_ += dn * keep;
  blend_e_ += de * keep;
  blend_t_ = t_;
  ++*blended_;
}

bool NavNode::hold_datum(const gnss_fix_t& m, double std_m, TimeUs taken) {
  const bool has_altitude = m.fix_type >= gnss_fix_t::FIX_3D;
  const double alt = has_altitude ? m.altitude : 0.0;
  auto restart = [&] {
    candidate_.Reset(m.latitude, m.longitude, alt);
    holding_ = true;
    hold_since_ = taken;
    hold_n_ = hold_e_ = hold_u_ = 0;
    held_ = 1;
  };
  if (!holding_) {
    restart();
  } else {
    double e = 0, n = 0, u = 0;
    candidate_.Forward(m.latitude, m.longitude, alt, e, n, u);
    const double mn = hold_n_ / held_, me = hold_e_ / held_;
    if (std::hypot(n - mn, e - me) > std::max(p_.datum_hold.consistent_m, 3 * std_m)) {
      ++*datum_restarts_;  // inconsistent with what was held: hold again from this fix
      restart();
    } else {
      hold_n_ += n;
      hold_e_ += e;
      hold_u_ += u;
      ++held_;
    }
  }
  if (to_seconds(taken - hold_since_) + 1e-9 < p_.datum_hold.hold_s) return false;
  double lat = 0, lon = 0, h = 0;
  candidate_.Reverse(hold_e_ / held_, hold_n_ / held_, hold_u_ / held_, lat, lon, h);
  datum_.Reset(lat, lon, h);
  have_datum_ = true;
  return true;
}

void NavNode::on_imu(const imu_t& m, TimeUs now) {
  if (!on_time(imu_fresh_, m.utime, now, "imu")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_imu_);
    return;
  }
  align(m.utime, now);  // the old rates up to this sample's time, then the new ones
  motion_.p = m.angular_rate[0];
  motion_.q = m.angular_rate[1];
  motion_.r = m.angular_rate[2];
  if (m.orientation_valid) {
    const double w = m.orientation[0], qx = m.orientation[1], qy = m.orientation[2],
                 qz = m.orientation[3];
    motion_.roll = wrap_pi(std::atan2(2 * (w * qx + qy * qz), 1 - 2 * (qx * qx + qy * qy)));
    motion_.pitch = std::asin(std::clamp(2 * (w * qy - qz * qx), -1.0, 1.0));
  } else {
    // Tilt from gravity (FRD, level at rest f = [0 0 -g]): f = -g [-sin(theta),
    // sin(phi) cos(theta), cos(phi) cos(theta)].
    const double fx = m.specific_force[0], fy = m.specific_force[1], fz = m.specific_force[2];
    if (std::hypot(fx, fy, fz) > 1.0) {
      motion_.roll = wrap_pi(std::atan2(-fy, -fz));
      motion_.pitch = std::atan2(fx, std::hypot(fy, fz));
    }
  }
  // The body's acceleration (FRD, forward and starboard): specific force plus gravity,
  // f + R^T [0 0 g] = f + g [-sin(theta), sin(phi) cos(theta), .].
  motion_.ax = m.specific_force[0] - kGravity * std::sin(motion_.pitch);
  motion_.ay = m.specific_force[1] + kGravity * std::sin(motion_.roll) * std::cos(motion_.pitch);
  motion_.az = m.specific_force[2] + kGravity * std::cos(motion_.roll) * std::cos(motion_.pitch);
  attitude_var_[0] = variance_or(m.orientation_covariance[0], p_.imu.default_attitude_std);
  attitude_var_[1] = variance_or(m.orientation_covariance[4], p_.imu.default_attitude_std);
  for (int i = 0; i < 3; ++i)
    rate_var_[i] = variance_or(m.angular_rate_covariance[4 * i], p_.imu.default_rate_std);
  imu_fresh_.mark(now, m.utime, clock_offset());
  last_imu_ = now;
  have_imu_ = true;
}

void NavNode::on_heading(const heading_t& m, TimeUs now) {
  if (!on_time(heading_fresh_, m.utime, now, "heading")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_heading_);
    return;
  }
  // A dual-antenna GNSS heading (true, no magnetic disturbance) is the heading source while it
  // is fresh: another source's heading is then left out (heading.other_ignored).
  const bool gnss = m.source == heading_t::SOURCE_GNSS;
  if (gnss) {
    last_gnss_heading_ = now;
    have_gnss_heading_ = true;
  } else if (have_gnss_heading_ && now - last_gnss_heading_ <= heading_fresh_.limit()) {
    ++*heading_other_ignored_;
    return;
  }
  heading_fresh_.mark(now, m.utime, clock_offset());
  const double lag = align(m.utime, now);
  const double rate = motion_.r - ekf_.x()(kBiasR);
  const double declination =
      m.reference == heading_t::REFERENCE_MAGNETIC ? p_.heading.declination : 0.0;
  const double z = wrap_pi(m.heading + declination + rate * lag);
  const double var = variance_or(m.variance, p_.heading.default_std);
  if (!heading_init_) {
    ekf_.set_heading(z, var);
    heading_init_ = true;
    return;
  }
  if (ekf_.update_heading(z, var, p_.heading.gate_chi2).accepted) {
    heading_gated_in_a_row_ = 0;
    return;
  }
  reject(*gate_heading_);
  if (++heading_gated_in_a_row_ >= p_.heading.reset_after) {
    ekf_.set_heading(z, var);
    heading_gated_in_a_row_ = 0;
    ++*resets_;
  }
}

void NavNode::on_pressure(const pressure_t& m, TimeUs now) {
  if (!on_time(pressure_fresh_, m.utime, now, "pressure")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_pressure_);
    return;
  }
  pressure_fresh_.mark(now, m.utime, clock_offset());
  if (p_.depth_source != DepthSource::kPressure) return;
  align(m.utime, now);
  const double var = variance_or(m.depth_variance, p_.depth.default_std_m);
  last_pressure_ = now;
  have_pressure_ = true;
  if (!depth_init_) {
    ekf_.set_depth(m.depth, var);
    depth_init_ = true;
    return;
  }
  if (ekf_.update_depth(m.depth, var, p_.depth.gate_chi2).accepted) {
    depth_gated_in_a_row_ = 0;
    return;
  }
  reject(*gate_depth_);
  if (++depth_gated_in_a_row_ >= p_.depth.reset_after) {
    // The estimate has left the pressure sensor: back to it (and w restarts at 0).
    ekf_.set_depth(m.depth, var);
    ekf_.set_state(kW, 0.0, sq(p_.initial_velocity_std_mps));
    depth_gated_in_a_row_ = 0;
    ++*resets_;
  }
}

void NavNode::on_dvl(const dvl_t& m, TimeUs now) {
  if (!on_time(dvl_fresh_, m.utime, now, "dvl")) return;
  if (checks::check(m) != nullptr) {
    reject(*bad_dvl_);
    return;
  }
  dvl_fresh_.mark(now, m.utime, clock_offset());
  if (!p_.dvl.enabled) return;
  if (!m.bottom_lock) {
    ++*dvl_no_lock_;
    return;
  }
  if (m.fom > p_.dvl.max_fom_mps) {
    reject(*dvl_fom_);
    return;
  }
  align(m.utime, now);
  // The DVL at lever arm r sees v + omega x r (body FRD): take omega x r off.
  const double wx = motion_.p, wy = motion_.q, wz = motion_.r - ekf_.x()(kBiasR);
  const double* a = p_.dvl.lever_arm_m;
  const Eigen::Vector3d z(m.velocity[0] - (wy * a[2] - wz * a[1]),
                          m.velocity[1] - (wz * a[0] - wx * a[2]),
                          m.velocity[2] - (wx * a[1] - wy * a[0]));
  Eigen::Matrix3d r =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(m.velocity_covariance);
  const double floor = sq(p_.dvl.min_std_mps);
  if (r.diagonal().isZero(0.0)) r = Eigen::Matrix3d::Identity() * sq(m.fom);
  for (int i = 0; i < 3; ++i) r(i, i) = std::max(r(i, i), floor);
  if (dvl_only_ && !position_init_) {
    // Dead reckoning starts here: the local frame's origin is where the first velocity was used.
    ekf_.set_position_ne(0.0, 0.0, sq(p_.dvl.initial_position_std_m));
    position_init_ = true;
    last_fix_ = now;
  }
  if (dvl_only_ && have_dvl_ && !dvl_fresh(now)) {
    // Back after a loss: the velocity restarts from this report, decorrelated from the position
    // (an update would move the dead-reckoned position by the report's noise times the long
    // correlation the outage built up: a jump of centimetres for nothing).
    ekf_.set_velocity_body(z(0), z(1), std::max(r(0, 0), r(1, 1)));
    ekf_.set_state(kW, z(2), r(2, 2));
    dvl_gated_in_a_row_ = 0;
  } else if (ekf_.update_velocity_body(z, r, p_.dvl.gate_chi2).accepted) {
    dvl_gated_in_a_row_ = 0;
  } else {
    reject(*gate_dvl_);
    if (++dvl_gated_in_a_row_ < p_.dvl.reset_after) return;
    ekf_.set_velocity_body(z(0), z(1), std::max(r(0, 0), r(1, 1)));
    ekf_.set_state(kW, z(2), r(2, 2));
    dvl_gated_in_a_row_ = 0;
    ++*resets_;
  }
  ++*dvl_used_;
  last_dvl_ = now;
  have_dvl_ = true;
}

bool NavNode::dvl_fresh(TimeUs now) const {
  return have_dvl_ && now - last_dvl_ <= from_seconds(p_.dvl.timeout_s);
}

std::int32_t NavNode::validity(TimeUs now) const {
  const Covariance& c = ekf_.P();
  const auto& l = p_.limits;
  std::int32_t v = 0;
  if (position_init_) {
    // On the DVL alone the position and velocity are only as good as its last report.
    const bool source = !dvl_only_ || dvl_fresh(now);
    if (source && largest_eigen(c(kN, kN), c(kN, kE), c(kE, kE)) <= sq(l.position_std_m))
      v |= odometry_t::VALID_POSITION;
    if (dvl_only_ || now - last_fix_ > from_seconds(p_.gnss.timeout_s))
      v |= odometry_t::DEAD_RECKONING;
    const double vmax = std::max({c(kU, kU), c(kV, kV), c(kW, kW)});
    if (source && vmax <= sq(l.velocity_std_mps)) v |= odometry_t::VALID_VELOCITY;
  }
  if (have_imu_ && now - last_imu_ <= from_seconds(p_.imu.timeout_s) && heading_init_ &&
      c(kPsi, kPsi) <= sq(l.heading_std))
    v |= odometry_t::VALID_ATTITUDE;
  if (p_.depth_source == DepthSource::kSurface ||
      (depth_init_ && now - last_pressure_ <= from_seconds(p_.depth.timeout_s) &&
       c(kD, kD) <= sq(l.depth_std_m)))
    v |= odometry_t::VALID_DEPTH;
  return v;
}

void NavNode::fill(TimeUs now) {
  const State& x = ekf_.x();
  const Covariance& c = ekf_.P();
  odom_.utime = now;
  for (int i = 0; i < 3; ++i) odom_.position[i] = x(kN + i);
  // What is left of a large correction (recovery.rate_mps): shrinking, and in the variance.
  if (blend_n_ != 0 || blend_e_ != 0) {
    const double b = std::hypot(blend_n_, blend_e_);
    const double left = std::max(0.0, b - p_.recovery.rate_mps * to_seconds(now - blend_t_));
    blend_t_ = now;
    blend_n_ *= left / b;
    blend_e_ *= left / b;
  }
  odom_.position[0] += blend_n_;
  odom_.position[1] += blend_e_;
  odom_.orientation[0] = motion_.roll;
  odom_.orientation[1] = motion_.pitch;
  odom_.orientation[2] = wrap_pi(x(kPsi));
  for (int i = 0; i < 3; ++i) odom_.velocity[i] = x(kU + i);
  odom_.velocity[3] = motion_.p;
  odom_.velocity[4] = motion_.q;
  odom_.velocity[5] = motion_.r - x(kBiasR);
  // Pose [n e d roll pitch yaw] <- states [n e d - - psi]; roll and pitch from the IMU.
  constexpr int pose[6] = {kN, kE, kD, -1, -1, kPsi};
  double* pc = odom_.pose_covariance.data();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      pc[6 * i + j] = (pose[i] >= 0 && pose[j] >= 0) ? c(pose[i], pose[j]) : 0.0;
  pc[0] += sq(blend_n_);
  pc[7] += sq(blend_e_);
  pc[6 * 3 + 3] = attitude_var_[0];
  pc[6 * 4 + 4] = attitude_var_[1];
  double* vc = odom_.velocity_covariance.data();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) vc[6 * i + j] = (i < 3 && j < 3) ? c(kU + i, kU + j) : 0.0;
  vc[6 * 3 + 3] = rate_var_[0];
  vc[6 * 4 + 4] = rate_var_[1];
  vc[6 * 5 + 5] = rate_var_[2] + c(kBiasR, kBiasR);
}

void NavNode::report_dead_reckoning(TimeUs now, std::int32_t valid) {
  const bool changed = valid != reported_valid_;
  if (!changed && dvl_status_at_ >= 0 && now - dvl_status_at_ < kUsPerSecond) return;
  if ((valid & odometry_t::DEAD_RECKONING) &&
      !(reported_valid_ >= 0 && (reported_valid_ & odometry_t::DEAD_RECKONING)))
    ++*dr_entered_;
  reported_valid_ = valid;
  const Covariance& c = ekf_.P();
  const double std_m = std::sqrt(largest_eigen(c(kN, kN), c(kN, kE), c(kE, kE)));
  const double dt = dvl_status_at_ >= 0 ? to_seconds(now - dvl_status_at_) : 0.0;
  const double growth_mm_s = dt > 0 ? 1e3 * (std_m - dvl_std_then_) / dt : 0.0;
  dvl_status_at_ = now;
  dvl_std_then_ = std_m;
  char b[200];
  int n = 0;
  if (!position_init_) {
    n = std::snprintf(b, sizeof b,
                      "waiting for the DVL's first bottom-lock velocity (dead reckoning starts "
                      "there)");
  } else if (!dvl_fresh(now)) {
    n = std::snprintf(b, sizeof b,
                      "DVL lost: no velocity used for %.1f s; position and velocity invalid, "
                      "1-sigma %.2f m growing %.1f mm/s",
                      to_seconds(now - last_dvl_), std_m, growth_mm_s);
  } else {
    n = std::snprintf(b, sizeof b,
                      "dead reckoning on the DVL: position 1-sigma %.3f m, growing %.2f mm/s",
                      std_m, growth_mm_s);
  }
  if (!(valid & odometry_t::VALID_ATTITUDE) && n > 0 && n < static_cast<int>(sizeof b))
    n += std::snprintf(b + n, sizeof b - static_cast<std::size_t>(n), "; invalid: attitude");
  if (!(valid & odometry_t::VALID_DEPTH) && n > 0 && n < static_cast<int>(sizeof b))
    std::snprintf(b + n, sizeof b - static_cast<std::size_t>(n), "; invalid: depth");
  dvl_status_.assign(b);
  const bool all = (valid & odometry_t::VALID_ALL) == odometry_t::VALID_ALL;
  set_health(all ? heartbeat_t::STATE_OK : heartbeat_t::STATE_DEGRADED, dvl_status_);
}

void NavNode::report(TimeUs now, std::int32_t valid) {
  if (dvl_only_) {
    report_dead_reckoning(now, valid);
    return;
  }
  if (valid == reported_valid_) return;
  const bool dr = valid & odometry_t::DEAD_RECKONING;
  if (dr && !(reported_valid_ >= 0 && (reported_valid_ & odometry_t::DEAD_RECKONING)))
    ++*dr_entered_;
  reported_valid_ = valid;
  std::string missing;
  auto need = [&](std::int32_t bit, const char* what) {
    if (valid & bit) return;
    missing += missing.empty() ? "" : ", ";
    missing += what;
  };
  if (p_.gnss.enabled || p_.dvl.enabled) need(odometry_t::VALID_POSITION, "position");
  if (p_.gnss.enabled || p_.dvl.enabled) need(odometry_t::VALID_VELOCITY, "velocity");
  need(odometry_t::VALID_ATTITUDE, "attitude");
  need(odometry_t::VALID_DEPTH, "depth");
  std::string status;
  if (!p_.gnss.enabled && !p_.dvl.enabled)
    status = "no position source (gnss.enabled false): position unavailable; ";
  if (dr) {
    char b[96];
    std::snprintf(b, sizeof b, "dead reckoning: no GNSS fix used for over %.1f s; ",
                  p_.gnss.timeout_s);
    status += b;
  }
  if (missing.empty()) {
    status += "valid";
    set_health(dr ? heartbeat_t::STATE_DEGRADED : heartbeat_t::STATE_OK, status);
  } else {
    status += "invalid: " + missing;
    set_health(heartbeat_t::STATE_DEGRADED, status);
  }
}

void NavNode::on_tick(TimeUs now) {
  advance(now);
  if (p_.depth_source == DepthSource::kSurface) {
    ekf_.set_state(kD, 0.0, kSurfaceVar);
    ekf_.set_state(kW, 0.0, kSurfaceVar);
  }
  for (int i : {kN, kE, kD}) ekf_.cap_variance(i, kPositionCap);
  for (int i : {kU, kV, kW}) ekf_.cap_variance(i, kVelocityCap);
  for (int i : {kBiasAx, kBiasAy}) ekf_.cap_variance(i, kAccelBiasCap);
  // The current: unobserved without the sway constraint, kept at its prior's variance.
  for (int i : {kCurrentN, kCurrentE}) ekf_.cap_variance(i, sq(p_.initial_current_std_mps));
  const bool imu_fresh = have_imu_ && now - last_imu_ <= from_seconds(p_.imu.timeout_s);
  if (p_.sway.enabled && imu_fresh && heading_init_ &&
      std::abs(ekf_.x()(kU)) >= p_.sway.min_speed_mps) {
    const auto& w = p_.sway;
    if (!ekf_.update_sway(motion_, w.std_mps, w.rate_gain_s, w.gate_chi2).accepted)
      reject(*gate_sway_);
  }
  const std::int32_t valid = validity(now);
  if (!(valid & odometry_t::VALID_POSITION)) ++*invalid_out_;
  if (p_.dvl.enabled) {
    const bool fresh = dvl_fresh(now);
    if (dvl_was_fresh_ && !fresh) ++*dvl_lost_;
    dvl_was_fresh_ = fresh;
  }
  odom_.valid = valid;
  fill(now);
  publish(channels::kOdometry, odom_);
  if (have_datum_ && (datum_sent_ < 0 || now - datum_sent_ >= kUsPerSecond)) {
    datum_sent_ = now;
    datum_t d{};
    d.utime = now;
    d.latitude = datum_.LatitudeOrigin();
    d.longitude = datum_.LongitudeOrigin();
    d.altitude = datum_.HeightOrigin();
    d.source = p_.fixed_datum ? datum_t::SOURCE_CONFIG : datum_t::SOURCE_FIRST_FIX;
    publish(channels::kDatum, d);
  }
  report(now, valid);
}

}  // namespace tiller::nav
