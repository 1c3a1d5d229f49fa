#!/usr/bin/env python3
"""Sway against the coupling's yaw friction in the time domain (docs/manoeuvres.md,
"Coupling friction"): a check of the describing function of `friction_table.py`.

The lane-change scene (its sin^4 rack pulse scaled down, so it starts a sway of a chosen
size) with the legal-limit trailer, 10 kg on the ball, payload spread (I_zz 450 kg m^2),
the coupling head (`ball_coupling.kind = "coupling_head"`) with the friction law
T tanh(w / w_reg) about its vertical axis (its x and y friction as in the file), rolling
above the critical speed. The articulation is the head's rotation about its z axis
(`ball_coupling` deflection `rz`); its envelope is the half-cycle amplitudes after the
pulse. A sway whose envelope shrinks started below the unstable limit cycle, one that
grows above it; the threshold is bracketed by bisection on the pulse's size and set
against the describing function's A* = 4 T / (pi w c_crit), with c_crit and w recomputed
here by `friction_table.c_crit`; the bracketing pair is run again at a tighter tolerance
and release rate. Then why they differ: the frictionless sway's growth against its
amplitude, without yaw damping and with the linear model's neutral damper c_crit, gives
the damper c_crit(A) that holds a sway of amplitude A neutral, and the trailer wheels'
load swing the mean loss of the trailer axle's cornering stiffness. Run from the
repository root after `cargo build --release` (about 15 min of CPU; writes out/fricsway/,
reused when run again, and docs/figures/sway_friction_envelopes.png; needs numpy, and
matplotlib for the figure).
"""
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np

from friction_table import HITCH, PLAIN_HEAD_N_M, c_crit, damper, mode
from sway_table import sway

TOWRIDE = "target/release/towride"
TRAILER = "vehicles/trailer/box_trailer.toml"
TYRE = "vehicles/tyres/trailer_155_80r13.tir"
OUT = "out/fricsway"
SETTLE_S = 6.0  # the car's own transients are gone by then; envelopes start here


def scene(scale):
    """A copy of the lane-change scene with its rack pulse times `scale` and the head's
    deflection, rate and torque as outputs; returns its path."""
    text = open("scenes/lane_change.toml").read()
    text = text.replace('"../', '"' + os.path.abspath("scenes") + '/../')
    start = text.index("value = [") + len("value = [")
    end = text.index("]", start)
    values = [f"{float(v) * scale:.12e}" for v in text[start:end].split(",")]
    text = text[:start] + ", ".join(values) + text[end:]
    for q, name in [("deflection", "head"), ("velocity", "head_rate"), ("force", "head_torque")]:
        text += f'\n[[output]]\nelement = "ball_coupling"\nquantity = "{q}"\nname = "{name}"\n'
    os.makedirs(OUT, exist_ok=True)
    path = f"{OUT}/scene_{scale:.6g}.toml"
    with open(path, "w") as f:
        f.write(text)
    return path


def run(scale, speed, t_n_m, w_reg, duration, rtol=None, atol_scale=None, z_law=None):
    """Runs one case; returns (t [s], articulation [rad], solver wall seconds, folder)."""
    s = scene(scale)
    law = f"{{ friction_torque_n_m = {PLAIN_HEAD_N_M}, release_rad_s = 0.01 }}"
    z = z_law or f"{{ friction_torque_n_m = {t_n_m}, release_rad_s = {w_reg} }}"
    name = f"v{speed}_T{t_n_m}_r{w_reg}_s{scale:.6g}_rtol{rtol}_a{atol_scale}_z{z_law}_d{duration:g}"
    out = f"{OUT}/{name.replace(' ', '')}"
    cmd = [TOWRIDE, "run", s, "--out", out,
           "--set", f"{s}:run.speed_km_h={speed}",
           "--set", f"{s}:run.duration_s={duration}",
           "--set", f"{s}:run.sample_rate_hz=100",
           "--set", f'{s}:scene.load_case="legal_limit_557kg"',
           "--set", f"{TRAILER}:load_case[4].payload.cm_m=[-2.46,0.0,0.745]",
           "--set", f"{TRAILER}:load_case[4].payload.inertia_kg_m2=[42.7,450.0,450.0]",
           "--set", f'{HITCH}:ball_coupling.kind="coupling_head"',
           "--set", f"{HITCH}:ball_coupling.coupling_head.damping_n_m_s_rad=[{law}, {law}, {z}]"]
    if rtol is not None:
        cmd += ["--set", f"{s}:solver.rtol={rtol}"]
    if atol_scale is not None:
        cmd += ["--set", f"{s}:run.atol_scale={atol_scale}"]
    # A finished run of the same case is reused (its folder name is its settings), so the
    # tables can be printed again without rerunning; a failed run still wrote its CSV.
    if not os.path.exists(f"{out}/summary.json"):
        subprocess.run(cmd, capture_output=True, text=True)
    with open(f"{out}/outputs.csv") as f:
        r = csv.reader(f)
        head = next(r)
        k = head.index("head.rz [rad]")
        rows = np.array([(float(x[0]), float(x[k])) for x in r])
    with open(f"{out}/summary.json") as f:
        wall = json.load(f)["wall_s"]
    return rows[:, 0], rows[:, 1], wall, out


def column(out, name):
    """One column of a run's outputs.csv."""
    with open(f"{out}/outputs.csv") as f:
        r = csv.reader(f)
        k = next(r).index(name)
        return np.array([float(x[k]) for x in r])


def envelope(t, x, after=SETTLE_S):
    """Half-cycle amplitudes of x after `after`: between consecutive zero crossings of x
    less its running mean over 1.25 s (about one sway period: a slow drift of the head's
    angle is not sway), the largest |x| (a parabola through the peak sample and its two
    neighbours). Returns arrays of the peaks' times and amplitudes."""
    n = int(round(1.25 / (t[1] - t[0])))
    x = x - np.convolve(x, np.ones(n) / n, mode="same")
    keep = (t >= after) & (t <= t[-1] - 1.25)
    t, x = t[keep], x[keep]
    cross = np.nonzero(np.signbit(x[:-1]) != np.signbit(x[1:]))[0]
    times, amps = [], []
    for a, b in zip(cross[:-1], cross[1:]):
        k = a + 1 + int(np.argmax(np.abs(x[a + 1:b + 1])))
        if 0 < k < len(x) - 1:
            y0, y1, y2 = abs(x[k - 1]), abs(x[k]), abs(x[k + 1])
            den = y0 - 2 * y1 + y2
            d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
            times.append(t[k] + d * (t[1] - t[0]))
            amps.append(y1 - 0.25 * (y0 - y2) * d)
    return np.array(times), np.array(amps)


def rate(times, amps, lo, hi):
    """Least-squares growth rate [1/s] of ln(amplitude) over peaks between times lo and hi."""
    m = (times >= lo) & (times <= hi)
    return np.polyfit(times[m], np.log(amps[m]), 1)[0]


SPEED = 300  # km/h, 67 km/h above the critical speed of the head without friction
T_N_M = 6.25  # the yaw friction whose A* is 1 deg at 300 km/h (friction_table.py)
DURATION_S = 18.0
FIT_S = (SETTLE_S, 17.0)  # the window whose envelope slope says decay or growth


def c_eq(t_n_m, w_reg, rate_amplitude):
    """The regularised law's describing function: the first harmonic of
    T tanh(V sin(th) / w_reg) over V, by quadrature (4 T / (pi V) when w_reg -> 0)."""
    th = np.linspace(0.0, 2.0 * np.pi, 4000, endpoint=False)
    v = rate_amplitude * np.sin(th)
    return 2.0 * np.mean(t_n_m * np.tanh(v / w_reg) * np.sin(th)) / rate_amplitude


def a_star_regularised(c_lin, w, w_reg):
    """The amplitude [deg] at which the regularised friction's c_eq equals c_lin."""
    lo, hi = 1e-4, 10.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if c_eq(T_N_M, w_reg, w * math.radians(mid)) > c_lin:
            lo = mid
        else:
            hi = mid
    return mid


def axle_stiffness_ratio(f_mean, f_swing):
    """The trailer axle's cornering stiffness averaged over a cycle in which its wheels'
    loads swing f_mean +- f_swing in opposition, over its value at f_mean: the .tir's
    K_ya ~ sin(PKY4 atan(F_z / (PKY2 FNOMIN))) (Pacejka 2012 (4.E25)), quasi-static."""
    v = {}
    with open(TYRE) as f:
        for line in f:
            parts = line.split("=")
            if len(parts) > 1 and parts[0].strip() in ("PKY2", "PKY4", "FNOMIN"):
                v[parts[0].strip()] = float(parts[1].split("$")[0])

    def k(fz):
        return np.sin(v["PKY4"] * np.arctan(fz / (v["PKY2"] * v["FNOMIN"])))

    th = np.linspace(0.0, 2.0 * np.pi, 1000, endpoint=False)
    swing = f_swing * np.sin(th)
    return np.mean(k(f_mean + swing) + k(f_mean - swing)) / (2.0 * k(f_mean))


def case(scale, w_reg=0.01, z_law=None, duration=DURATION_S, **kw):
    t, x, wall, out = run(scale, SPEED, T_N_M, w_reg, duration, z_law=z_law, **kw)
    tp, a = envelope(t, x)
    return {"scale": scale, "a0": math.degrees(a[0]), "sigma": rate(tp, a, *FIT_S),
            "a_end": math.degrees(a[-1]), "t_end": tp[-1], "wall": wall, "out": out, "t": t,
            "times": tp, "amps": np.degrees(a)}


def local_rates(c, n=4):
    """Growth rate over n half-cycles against the amplitude (their geometric mean)."""
    t, a = c["times"], c["amps"]
    return (np.sqrt(a[n:] * a[:-n]), np.log(a[n:] / a[:-n]) / (t[n:] - t[:-n]))


def merged_rates(runs):
    """local_rates of several runs, sorted by amplitude."""
    a, r = (np.concatenate(v) for v in zip(*(local_rates(c) for c in runs)))
    k = np.argsort(a)
    return a[k], r[k]


def threshold(lo, hi):
    """The start amplitude where the envelope's slope is zero, between a decaying and a
    growing case (linear in the slope)."""
    return lo["a0"] + (hi["a0"] - lo["a0"]) * -lo["sigma"] / (hi["sigma"] - lo["sigma"])


def bisect(lo_scale, hi_scale, steps, **kw):
    cases = []
    lo, hi = None, None
    for s in [lo_scale, hi_scale] + [None] * steps:
        if s is None:
            s = 0.5 * (lo["scale"] + hi["scale"])
        c = case(s, **kw)
        cases.append(c)
        if c["sigma"] < 0.0:
            lo = c
        else:
            hi = c
        print(f"#   scale {s:.4f}: start {c['a0']:.3f} deg, slope {c['sigma']:+.4f} 1/s, "
              f"{c['wall']:.0f} s", file=sys.stderr, flush=True)
    return cases, lo, hi


def row(label, c, a_star):
    verdict = "decays" if c["sigma"] < 0 else "grows"
    return (f"| {label} | {c['scale']:.4f} | {c['a0']:.3f} | {c['a0'] / a_star:.2f} "
            f"| {c['sigma']:+.4f} | {c['a_end']:.3f} at {c['t_end']:.1f} s | {verdict} |")


def figure(cases, viscous, c_lin, a_star, a_lc, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 5.2))
    for c in sorted(cases, key=lambda c: -c["a0"]):
        grows = c["sigma"] >= 0
        ax.semilogy(c["times"], c["amps"], "-", color="tab:red" if grows else "tab:blue",
                    lw=1.2, label=f"{c['a0']:.2f} deg: " + ("grows" if grows else "decays"))
    ax.axhline(a_star, color="k", ls="--", lw=1, label=f"describing function A* {a_star:.2f} deg")
    ax.axhline(a_lc, color="tab:green", ls=":", lw=1.5, label=f"time-domain threshold {a_lc:.2f} deg")
    ax.set_ylim(0.05, 5)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("articulation amplitude [deg]")
    ax.set_title(f"{SPEED} km/h, yaw friction {T_N_M} N m, release 0.01 rad/s")
    ax.legend(fontsize=7)
    for c in cases:
        a, r = local_rates(c)
        bx.plot(a, r, ".", ms=3, color="tab:red" if c["sigma"] >= 0 else "tab:blue",
                label=None)
    for (label, runs), col in zip(viscous, ["tab:orange", "tab:purple"]):
        for k, c in enumerate(runs):
            a, r = local_rates(c)
            bx.plot(a, r, "-", color=col, label=(label if k == 0 else None))
    bx.axhline(0, color="k", lw=0.8)
    bx.axvline(a_star, color="k", ls="--", lw=1, label="A*")
    bx.axvline(a_lc, color="tab:green", ls=":", lw=1.5, label="time-domain threshold")
    bx.set_xscale("log")
    bx.set_xlim(0.1, 3)
    ticks = [0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 2.0, 3.0]
    bx.set_xticks(ticks, [f"{v:g}" for v in ticks])
    bx.minorticks_off()
    bx.set_ylim(-0.6, 0.3)
    bx.set_xlabel("articulation amplitude [deg]")
    bx.set_ylabel("envelope growth rate over 2 cycles [1/s]")
    bx.set_title("dots: friction runs; lines: viscous yaw damper instead")
    bx.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    c_lin, m = c_crit(SPEED)
    w = 2.0 * math.pi * m["damped_hz"]
    a_star = math.degrees(4.0 * T_N_M / (math.pi * w * c_lin))
    print(f"{SPEED} km/h: c_crit {c_lin:.1f} N m s/rad, sway {m['damped_hz']:.3f} Hz; "
          f"T {T_N_M} N m -> A* {a_star:.3f} deg (Coulomb); with the tanh law "
          + ", ".join(f"{a_star_regularised(c_lin, w, r):.3f} deg at {r} rad/s"
                      for r in (0.01, 0.003, 0.001)))
    print()
    print("| case | pulse scale | start amplitude [deg] | / A* | envelope slope 6-17 s [1/s] "
          "| last amplitude [deg] | verdict |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    cases, lo, hi = bisect(0.14, 0.18, 2)
    # Further from the threshold, over 30 s: a small start, and one far enough above to
    # grow until a wheel lifts and the run stops.
    cases += [case(0.1, duration=30.0), case(0.2, duration=40.0)]
    for c in sorted(cases, key=lambda c: c["scale"]):
        print(row("release 0.01 rad/s", c, a_star))
    a_lc = threshold(lo, hi)
    checks = []
    # The bracketing pair again at a tighter tolerance, and there with the friction's
    # release rate cut to 0.003 and 0.001 rad/s. (At the scene's rtol 1e-5 with its
    # default atol a case at 0.003 rad/s got 6.35 s into the run in 28 min, most steps
    # refused at the friction's reversals; the tighter atol makes them cheap.)
    tight = {"rtol": 1e-6, "atol_scale": 1e-3}
    for label, kw in [("rtol 1e-6, atol x 1e-3", tight),
                      ("same, release 0.003 rad/s", {"w_reg": 0.003, **tight}),
                      ("same, release 0.001 rad/s", {"w_reg": 0.001, **tight})]:
        pair = [case(c["scale"], **kw) for c in (lo, hi)]
        for c in pair:
            print(row(label, c, a_star))
        checks.append((label, pair))
    print()
    print("| case | threshold (start amplitude of zero slope) [deg] | / A* |")
    print("| --- | --- | --- |")
    print(f"| release 0.01 rad/s | {a_lc:.3f} | {a_lc / a_star:.2f} |")
    for label, (l, h) in checks:
        a = threshold(l, h) if l["sigma"] < 0 <= h["sigma"] else float("nan")
        print(f"| {label} | {a:.3f} | {a / a_star:.2f} |")
    # The frictionless head's own growth against amplitude: no yaw friction, and the
    # linear model's neutral damper c_crit in its place.
    viscous = [("no yaw damping", [case(0.06, z_law="0", duration=24.0)]),
               (f"yaw damper c_crit {c_lin:.1f} N m s/rad", [case(s, z_law=f"{c_lin}", duration=24.0)
                                            for s in (0.08, 0.13, 0.16, 0.2)])]
    print()
    print("| articulation amplitude [deg] | growth, no yaw damping [1/s] "
          "| growth, yaw damper c_crit [1/s] | c_crit at that amplitude [N m s/rad] "
          "| friction's c_eq there [N m s/rad] |")
    print("| --- | --- | --- | --- | --- |")
    (a0, r0), (a1, r1) = (merged_rates(runs) for _, runs in viscous)
    prev, a_df, t_1deg = None, float("nan"), float("nan")
    for a in [0.35, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2]:
        # Only where both have measured points within 10 % (no bridging of gaps).
        if min(abs(a0 / a - 1.0)) > 0.1 or min(abs(a1 / a - 1.0)) > 0.1:
            continue
        s0 = np.interp(math.log(a), np.log(a0), r0)
        s1 = np.interp(math.log(a), np.log(a1), r1)
        c_a = c_lin * s0 / (s0 - s1)
        c_eq = 4.0 * T_N_M / (math.pi * w * math.radians(a))
        print(f"| {a} | {s0:+.4f} | {s1:+.4f} | {c_a:.1f} | {c_eq:.1f} |")
        if a == 1.0:
            t_1deg = math.pi * w * math.radians(a) * c_a / 4.0
        if prev and prev[1] > 0.0 >= c_eq - c_a:
            a_df = prev[0] + (a - prev[0]) * prev[1] / (prev[1] - (c_eq - c_a))
        prev = (a, c_eq - c_a)
    print()
    print(f"The describing function with c_crit at the sway's amplitude: threshold "
          f"{a_df:.3f} deg (with the linear c_crit: {a_star:.3f} deg); the friction that "
          f"would hold 1 deg with c_crit(1 deg): {t_1deg:.1f} N m")
    # What changes with amplitude in the frictionless run: the trailer wheels' load swing
    # over the cycle nearest 1 deg.
    c = viscous[0][1][0]
    k = int(np.argmin(abs(c["amps"] - 1.0)))
    fz = column(c["out"], "tyre_tl_fz [N]")
    near = abs(c["t"] - c["times"][k]) < 0.62
    print(f"No yaw damping, {c['amps'][k]:.2f} deg at {c['times'][k]:.1f} s: trailer left wheel "
          f"load {np.mean(fz[near]):.0f} N +- {0.5 * np.ptp(fz[near]):.0f} N")
    ratio = axle_stiffness_ratio(np.mean(fz[near]), 0.5 * np.ptp(fz[near]))
    m0 = mode(SPEED, 0.0)
    m1 = sway(SPEED, -2.46, 450.0, 450.0, damper(0.0)
              + ["--set", f"{TYRE}:SCALING_COEFFICIENTS.LKY={ratio:.4f}"])
    print(f"Trailer axle's cornering stiffness averaged over that load swing: x {ratio:.4f}; "
          f"the linear sway without yaw damping at LKY = {ratio:.4f}: "
          f"{m1['real_1_per_s']:+.4f} 1/s (LKY = 1: {m0['real_1_per_s']:+.4f} 1/s)")
    os.makedirs("docs/figures", exist_ok=True)
    try:
        figure([c for c in cases], viscous, c_lin, a_star, a_lc,
               "docs/figures/sway_friction_envelopes.png")
    except ImportError:
        print("(no matplotlib: no figure)", file=sys.stderr)


if __name__ == "__main__":
    main()
