#!/usr/bin/env python3
"""Sway (snaking) mode of the car with the legal-limit trailer against speed, for two nose
loads and two payload yaw inertias, from `towride linear` (docs/manoeuvres.md, "Sway").

Each point linearises the default scene at 0.05 s (rolling at speed, the ramp 60 m ahead)
with the trailer's `legal_limit_557kg` load case, its payload moved and its inertia set by
`--set`; the sway mode is the least damped oscillation between 0.3 and 3 Hz named after
the trailer box's lateral or yaw motion. The critical speed is interpolated where its
damping ratio changes sign. A second table gives the critical speed against the front
axle's bump steer (the tie rod's inner height moved by `--set`; the bump steer is the
design analysis's, from a run's summary). Run from the repository root after
`cargo build --release`.
"""
import json
import subprocess

TOWRIDE = "target/release/towride"
TRAILER = "vehicles/trailer/box_trailer.toml"
FRONT = "vehicles/fabia/front_mcpherson.toml"


def tie_rod(z):
    """The `--set` arguments that put the inner tie rod joints (and the rack) at height z."""
    return ["--set", f"{FRONT}:hardpoints.tie_rod_inner_m=[-0.150, 0.330, {z}]",
            "--set", f"{FRONT}:steering_rack.cm_m=[-0.150, 0.0, {z}]"]


def bump_steer(z):
    """The front axle's bump steer [deg/m] with the inner tie rod joints at height z."""
    cmd = [TOWRIDE, "run", "scenes/default.toml", "--out", "out/sway_bump",
           "--set", "scenes/default.toml:run.duration_s=0.01"] + tie_rod(z)
    subprocess.run(cmd, capture_output=True, text=True, check=True)
    with open("out/sway_bump/summary.json") as f:
        corners = json.load(f)["scene"]["design"]["car_corners"]
    return corners[0]["bump_steer_deg_m"]


def sway(speed_km_h, payload_x_m, izz, iyy, extra=()):
    cmd = [TOWRIDE, "linear", "scenes/default.toml", "--at", "0.05", "--json",
           "--out", "out/sway_linear",
           "--set", f"scenes/default.toml:run.speed_km_h={speed_km_h}",
           "--set", "scenes/default.toml:road.obstacle_ahead_m=60",
           "--set", 'scenes/default.toml:scene.load_case="legal_limit_557kg"',
           "--set", f"{TRAILER}:load_case[4].payload.cm_m=[{payload_x_m},0.0,0.745]",
           "--set", f"{TRAILER}:load_case[4].payload.inertia_kg_m2=[42.7,{iyy},{izz}]"]
    cmd += list(extra)
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    modes = json.loads(out)["result"]["modes"]
    sway_modes = [m for m in modes
                  if m["kind"] != "zero" and 0.3 < m["damped_hz"] < 3.0
                  and "trailer_box" in m["name"]
                  and ("lateral" in m["name"] or "yaw" in m["name"])]
    return min(sway_modes, key=lambda m: m["damping_ratio"])


def critical(speeds, payload_x_m, izz, iyy, extra=()):
    """Cells (frequency / damping ratio) over `speeds` and the critical speed or None."""
    cells, prev, crit = [], None, None
    for v in speeds:
        m = sway(v, payload_x_m, izz, iyy, extra)
        z = m["damping_ratio"]
        cells.append(f"{m['damped_hz']:.2f} Hz / {z:+.3f}")
        if prev and prev[1] > 0 >= z and crit is None:
            crit = prev[0] + (v - prev[0]) * prev[1] / (prev[1] - z)
        prev = (v, z)
    return cells, crit


def main():
    speeds = range(60, 261, 20)
    print("| nose load [kg] | payload I_zz [kg m^2] | "
          + " | ".join(f"{v} km/h" for v in speeds) + " | critical speed [km/h] |")
    print("| --- | --- | " + " | ".join("---" for _ in speeds) + " | --- |")
    # Nose load: the empty trailer's ~10 kg, plus 457 kg x (x + 2.46) / 2.46.
    for nose, x in [(10, -2.46), (35, -2.325)]:
        # The compact stack (the load case's own inertia), and the same mass split in two
        # halves at the box's ends, 0.99 m before and behind its centre: 457 x 0.99^2 = 450.
        for izz, iyy in [(135.6, 102.2), (450.0, 450.0)]:
            cells, crit = critical(speeds, x, izz, iyy)
            verdict = "none below 260" if crit is None else f"{crit:.0f}"
            print(f"| {nose} | {izz} | " + " | ".join(cells) + f" | {verdict} |")
    print()
    print("| inner tie rod height [m] | front bump steer [deg/m] | "
          "critical speed, 10 kg on the ball [km/h] | critical speed, 35 kg [km/h] |")
    print("| --- | --- | --- | --- |")
    for z in [0.3144, 0.3128, 0.3104, 0.3084, 0.3064, 0.2900]:
        verdicts = []
        for x in [-2.46, -2.325]:
            _, crit = critical(speeds, x, 450.0, 450.0, tie_rod(z))
            verdicts.append("none below 260" if crit is None else f"{crit:.0f}")
        print(f"| {z} | {bump_steer(z):.1f} | " + " | ".join(verdicts) + " |")


if __name__ == "__main__":
    main()
