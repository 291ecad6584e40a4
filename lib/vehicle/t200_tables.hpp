// Blue Robotics T200 thruster, bollard thrust against the ESC pulse at 12 V and 16 V: Blue
// Robotics, "T200 Public Performance Data 10-20V September 2019" (spreadsheet,
// https://cad.bluerobotics.com/T200-Public-Performance-Data-10-20V-September-2019.xlsx; Basic
// ESC, 1100..1900 us), sheets "12 V" and "16 V", column "Force (Kg f)", every 20 us plus each
// sheet's dead-band edges (12 V: zero 1464..1536 us; 16 V: zero 1472..1528 us). Both on one pulse
// grid so that the voltage blend (ThrustCurve::voltage_table) is per point. Internal to
// thrust_curve.cpp.
#pragma once

#include <array>

namespace tiller::t200 {

inline constexpr std::array<double, 44> kPulseUs = {
    1100, 1120, 1140, 1160, 1180, 1200, 1220, 1240, 1260, 1280, 1300, 1320, 1340, 1360, 1380,
    1400, 1420, 1440, 1460, 1464, 1468, 1472, 1528, 1532, 1536, 1540, 1560, 1580, 1600, 1620,
    1640, 1660, 1680, 1700, 1720, 1740, 1760, 1780, 1800, 1820, 1840, 1860, 1880, 1900};
inline constexpr std::array<double, 44> kKgf12V = {
    -2.90, -2.76, -2.56, -2.34, -2.14, -1.95, -1.73, -1.53, -1.37, -1.19, -1.02,
    -0.87, -0.72, -0.57, -0.44, -0.32, -0.20, -0.11, -0.04, 0.00,  0.00,  0.00,
    0.00,  0.00,  0.00,  0.04,  0.13,  0.25,  0.39,  0.55,  0.71,  0.89,  1.08,
    1.28,  1.48,  1.71,  1.92,  2.18,  2.46,  2.71,  3.01,  3.26,  3.50,  3.71};
inline constexpr std::array<double, 44> kKgf16V = {
    -4.07, -3.87, -3.66, -3.31, -2.99, -2.71, -2.45, -2.20, -1.94, -1.67, -1.44,
    -1.20, -1.02, -0.82, -0.65, -0.48, -0.32, -0.18, -0.07, -0.05, -0.04, 0.00,
    0.00,  0.04,  0.05,  0.08,  0.22,  0.40,  0.60,  0.82,  1.03,  1.28,  1.54,
    1.82,  2.12,  2.43,  2.76,  3.11,  3.42,  3.82,  4.25,  4.65,  5.01,  5.25};

}  // namespace tiller::t200
