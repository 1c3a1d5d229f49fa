#!/usr/bin/env python3
"""Bump steer and camber of the Fabia's McPherson front axle by position analysis, an
independent check of the velocity analysis in `crates/towride-app/src/vehicle/strut.rs`
(docs/vehicle.md, "The front tie rod's height").

The body is held and the bushings rigid. Unknowns: the knuckle's rotation vector and
translation about the design position, and the lower arm's angle about its pivot axis.
Conditions: the ball joint on the arm, the strut axis through the top mount (two), the tie
rod's length, the wheel centre at the asked height. Solved by least squares at each
height, continued from the previous one.

Usage: mcpherson_bump.py [INNER_TIE_ROD_Z_M]   (default: the shipped 0.3104 m)
Prints toe (toe-in positive) and camber (top out positive) of the left wheel [deg]
against the wheel centre's rise [mm], and the slope at the design position [deg/m].
"""
import sys

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

# Hardpoints of vehicles/fabia/front_mcpherson.toml, left side [m].
W = np.array([0.0, 0.7175, 0.273])
A1 = np.array([0.12, 0.37, 0.190])
A2 = np.array([-0.22, 0.39, 0.200])
B = np.array([0.0, 0.680, 0.160])
S = np.array([-0.012, 0.640, 0.330])
T = np.array([-0.035, 0.555, 0.760])
O = np.array([-0.140, 0.660, 0.300])
I = np.array([-0.150, 0.330, float(sys.argv[1]) if len(sys.argv) > 1 else 0.3104])
L = np.linalg.norm(O - I)
AXIS = (A2 - A1) / np.linalg.norm(A2 - A1)
U0 = (T - S) / np.linalg.norm(T - S)
P1 = np.cross(U0, [1.0, 0.0, 0.0])
P1 /= np.linalg.norm(P1)
P2 = np.cross(U0, P1)


def pose(x):
    r = Rotation.from_rotvec(x[0:3])
    return r, (lambda p: r.apply(p - W) + W + x[3:6]), x[6]


def residual(x, z):
    r, on_knuckle, arm = pose(x)
    ball_on_arm = A1 + Rotation.from_rotvec(AXIS * arm).apply(B - A1)
    u = r.apply(U0)
    d = T - on_knuckle(S)
    d = d - np.dot(d, u) * u
    return [*(on_knuckle(B) - ball_on_arm),
            np.dot(d, r.apply(P1)), np.dot(d, r.apply(P2)),
            np.linalg.norm(on_knuckle(O) - I) - L,
            on_knuckle(W)[2] - z]


def toe_camber(x):
    spin = pose(x)[0].apply([0.0, 1.0, 0.0])
    return np.degrees(np.arctan2(spin[0], spin[1])), -np.degrees(np.arcsin(spin[2]))


def main():
    rows = []
    for branch in ([-0.02, -0.04, -0.06, -0.08], [0.02, 0.04, 0.06, 0.08]):
        x = np.zeros(7)
        for dz in branch:
            x = least_squares(residual, x, args=(W[2] + dz,),
                              xtol=1e-15, ftol=1e-15, gtol=1e-15).x
            rows.append((dz, *toe_camber(x)))
    rows.append((0.0, 0.0, 0.0))
    rows.sort()
    print("rise [mm] | toe [deg] | camber [deg]")
    for dz, toe, camber in rows:
        print(f"{dz * 1000:9.0f} | {toe:9.3f} | {camber:9.3f}")
    r = np.array(rows)
    print(f"at the design position: bump steer {np.polyfit(r[:, 0], r[:, 1], 3)[-2]:.2f} deg/m, "
          f"camber gain {np.polyfit(r[:, 0], r[:, 2], 3)[-2]:.2f} deg/m")


if __name__ == "__main__":
    main()
