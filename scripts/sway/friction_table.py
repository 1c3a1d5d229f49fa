#!/usr/bin/env python3
"""Sway and the coupling's yaw friction, by the describing function (docs/manoeuvres.md,
"Coupling friction").

A friction torque T about the ball's vertical axis takes 4 T A per cycle out of a sway of
articulation amplitude A; a viscous damper c takes pi c w A^2 (w the sway's angular
frequency), so over a cycle the friction acts as c_eq = 4 T / (pi w A): large for small
sways (they stick), small for large ones. Above the critical speed the linear model's
sway grows; a viscous yaw damper c_crit(V) at the coupling brings its damping ratio back
to zero. A sway of amplitude A then dies out when c_eq(A) > c_crit(V), i.e. below
A* = 4 T / (pi w c_crit), and grows above it; the friction a coupling needs to stop a
sway of amplitude A is T = pi w A c_crit / 4.

c_crit(V) is found by bisection on the coupling head's z damping (the shipped head without
play, `ball_coupling.kind = "coupling_head"`, its x and y friction left as in the file),
for the legal-limit trailer with 10 kg on the ball and its payload spread (I_zz 450 kg m^2),
each point the default scene linearised rolling at speed with the ramp 60 m ahead. Run
from the repository root after `cargo build --release`.
"""
import math

from sway_table import sway

HITCH = "vehicles/fabia/hitch.toml"
FRICTION = "{ friction_torque_n_m = 1.35, release_rad_s = 0.01 }"
PLAIN_HEAD_N_M = 1.35  # the file's plain head: mu N r = 0.15 x 360 N x 0.025 m [assumed]


def damper(c):
    return ["--set", f'{HITCH}:ball_coupling.kind="coupling_head"',
            "--set", f"{HITCH}:ball_coupling.coupling_head.damping_n_m_s_rad="
                     f"[{FRICTION}, {FRICTION}, {c}]"]


def mode(v, c):
    return sway(v, -2.46, 450.0, 450.0, damper(c))


def c_crit(v, hi=400.0):
    """The yaw damping [N m s/rad] at which the sway's damping ratio is zero at v km/h."""
    lo = 0.0
    if mode(v, lo)["damping_ratio"] > 0.0:
        return 0.0, mode(v, lo)
    for _ in range(12):
        mid = 0.5 * (lo + hi)
        if mode(v, mid)["damping_ratio"] > 0.0:
            hi = mid
        else:
            lo = mid
    return hi, mode(v, hi)


def main():
    print("| speed [km/h] | damping ratio without a damper | c_crit [N m s/rad] | sway frequency [Hz] "
          "| A* of the plain head's 1.35 N m [deg] | T to stop a 1 deg sway [N m] "
          "| T to stop a 3 deg sway [N m] |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for v in [200, 220, 240, 260, 280, 300]:
        z0 = mode(v, 0.0)["damping_ratio"]
        c, m = c_crit(v)
        w = 2.0 * math.pi * m["damped_hz"]
        if c == 0.0:
            print(f"| {v} | {z0:+.4f} | 0 (stable) | {m['damped_hz']:.3f} | any | 0 | 0 |")
            continue
        a_star = math.degrees(4.0 * PLAIN_HEAD_N_M / (math.pi * w * c))
        t = [math.pi * w * math.radians(a) * c / 4.0 for a in (1.0, 3.0)]
        print(f"| {v} | {z0:+.4f} | {c:.1f} | {m['damped_hz']:.3f} | {a_star:.2f} "
              f"| {t[0]:.1f} | {t[1]:.1f} |")


if __name__ == "__main__":
    main()
