"""The thrust (N) of a normalised thruster command on the BlueROV2-class vehicle: the T200 curve
t200_12v (the table in lib/vehicle/thrust_curve.cpp: pulse width -> kgf, 1464..1536 us the dead
band), so that a command crossing the dead band (+-0.09 with no thrust either side) is not taken
for a thrust step. Shared by the ROV live tests (rov_modes_live_test.py, rov_dvl_live_test.py)."""

CURVE_U = [(us - 1500) / 400 for us in (1100, 1200, 1300, 1400, 1464, 1536, 1600, 1700, 1800, 1900)]
CURVE_N = [k * 9.80665 for k in (-2.90, -1.95, -1.02, -0.32, 0, 0, 0.39, 1.28, 2.46, 3.71)]


def newtons(u):
    u = min(max(u, CURVE_U[0]), CURVE_U[-1])
    i = next(i for i in range(1, len(CURVE_U)) if u <= CURVE_U[i])
    return CURVE_N[i - 1] + (CURVE_N[i] - CURVE_N[i - 1]) * (u - CURVE_U[i - 1]) / (CURVE_U[i] - CURVE_U[i - 1])
