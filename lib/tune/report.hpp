// tiller-tune's printed tables: the identified model against a reference model (the vehicle
// file's, or the simulator's with its scales), each parameter with its 95 % interval (2 sigma)
// and the difference in %; the drag at the fastest speed flown (the figure that matters where a
// parameter is near 0, such as the Otter's quadratic surge drag); and the proposed changes.
#pragma once

#include <string>

#include "tune/identify.hpp"
#include "tune/propose.hpp"

namespace tiller::tune {

// The fastest |velocity| of each identified axis in the record (m/s, rad/s).
std::array<double, kAxes> fastest(const Record& r, const Identified& id);

// Relative differences (identified - reference) / reference, per axis: mass, linear, quadratic
// (NaN where the reference is 0), drag at the fastest speed; and the time constant's.
struct Differences {
  std::array<std::array<double, 4>, kAxes> axis{};  // mass, linear, quadratic, drag at top speed
  double time_constant = 0;
};
Differences differences(const Identified& id, const std::array<AxisTruth, kAxes>& ref,
                        double ref_time_constant, const std::array<double, kAxes>& top);

std::string identify_report(const Identified& id, const std::array<AxisTruth, kAxes>& ref,
                            double ref_time_constant, const std::array<double, kAxes>& top,
                            const std::string& ref_name);
std::string proposal_report(const Proposal& p);

}  // namespace tiller::tune
