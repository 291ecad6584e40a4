// Thrust curve of one thruster: normalised motor command u in [-1, 1] -> thrust in N along the
// motor's own positive axis, and the inverse (thrust in N -> command). Shared by the mixer
// (thrust -> command) and the simulator's thruster model (command -> thrust).
//
// Kinds:
//   linear     T = F*u (u >= 0), R*u (u < 0)            F, R: full forward / reverse thrust, N
//   quadratic  T = F*u*|u| (u >= 0), R*u*|u| (u < 0)     fixed-pitch propeller, T ~ k*n*|n| with
//                                                        u = n / n_max (Otter, Fossen otter.py)
//   table      piecewise linear through (u_k, T_k), u_k increasing from -1 to 1, T_k
//              non-decreasing (a flat band around 0 is the ESC/propeller dead band)
//   polynomial T = sum c_k u^k; only the monotonic part around u = 0 is used, so a command
//              never goes past the curve's peak (the BlueROV2 T200 fit peaks before |u| = 1)
// Presets: "t200_12v" (Blue Robotics T200 at 12 V, September 2019 data, 1100..1900 us mapped to
// -1..1 with 1500 us neutral, zero band 1464..1536 us; kgf * 9.80665; 10 points), "t200_poly" (the
// BlueROV2 polynomial of von Benzon et al. 2022, doi:10.3390/jmse10121898,
// docs/adding-a-vehicle.md); from the same data's 12 V and 16 V sheets every 20 us
// (vehicle/t200_tables.hpp): "t200_16v", "t200_14v8" (the 12 and 16 V sheets blended at 14.8 V)
// and "t200", the voltage table over 12..16 V that tiller-mixer sets from TILLER_POWER.
//
// thrust() and command() never allocate and never throw; command() clamps to the curve's range
// and returns 0 for zero thrust (neutral stays neutral even inside a dead band).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tiller {

class ThrustCurve {
 public:
  enum class Kind { kLinear, kQuadratic, kTable, kPolynomial };

  // Constructors throw std::invalid_argument with a readable reason on bad parameters.
  static ThrustCurve linear(double forward_n, double reverse_n);
  static ThrustCurve quadratic(double forward_n, double reverse_n);
  static ThrustCurve table(std::vector<double> command, std::vector<double> thrust_n);
  static ThrustCurve polynomial(std::vector<double> coefficients);  // c0, c1, c2, ...
  // A table whose thrust depends on the supply voltage: thrust_lo at v_lo volts and thrust_hi at
  // v_hi (each a valid table on the same commands), blended point by point in proportion to the
  // voltage by set_supply_voltage() (clamped to [v_lo, v_hi]). It starts at v_hi: the least
  // thrust for a command is assumed until a voltage is told.
  static ThrustCurve voltage_table(std::vector<double> command, std::vector<double> thrust_lo,
                                   double v_lo, std::vector<double> thrust_hi, double v_hi);
  static ThrustCurve preset(std::string_view name);
  static std::vector<std::string> preset_names();

  ThrustCurve() : ThrustCurve(linear(1.0, 1.0)) {}

  // Command (clamped to [min_command, max_command]) -> thrust, N.
  double thrust(double u) const;
  // Thrust, N -> command in [min_command(), max_command()] (clamped to the curve's range).
  double command(double thrust_n) const;

  double max_forward_n() const { return t_max_; }   // thrust at max_command(), > 0
  double max_reverse_n() const { return -t_min_; }  // |thrust| at min_command(), > 0
  double min_command() const { return u_min_; }     // >= -1
  double max_command() const { return u_max_; }     // <= 1
  Kind kind() const { return kind_; }
  // The supply voltage the curve is at (V; 0: none given). Only a voltage table changes with
  // set_supply_voltage(); on other curves it does nothing.
  // No allocation; a NaN or infinite voltage is ignored.
  bool voltage_dependent() const { return !t_lo_.empty(); }
  void set_supply_voltage(double volts);
  double supply_voltage() const { return volts_; }
  double voltage_low() const { return v_lo_; }
  double voltage_high() const { return v_hi_; }
  const std::string& description() const { return description_; }

 private:
  ThrustCurve(Kind k) : kind_(k) {}
  double poly(double u) const;
  double poly_deriv(double u) const;
  void finish_monotone_table();  // builds the inverse samples (polynomial)

  Kind kind_;
  std::string description_;
  double fwd_ = 1, rev_ = 1;         // linear / quadratic
  std::vector<double> u_, t_;        // table points, or polynomial samples for the inverse
  std::vector<double> du_dt_;        // table: inverse slope per segment
  std::vector<double> c_;            // polynomial coefficients
  double u_min_ = -1, u_max_ = 1;    // usable command range
  double t_min_ = -1, t_max_ = 1;    // thrust at u_min_ / u_max_
  std::vector<double> t_lo_, t_hi_;  // voltage table: thrust at v_lo_ / v_hi_ (t_: the blend)
  double v_lo_ = 0, v_hi_ = 0, volts_ = 0;
};

}  // namespace tiller
