"""The ten hitch crossbeam variants of the default scene, run in parallel threads.

    python examples/python/hitch_variants.py [--jobs N] [--png hitch_fx.png]

Prints each variant's hitch_fx max and min and the wall time; plots hitch_fx over time
for every variant when matplotlib is installed. The same ten cases from the CLI:
``towride sweep examples/python/hitch_variants_50.toml``.
"""

import argparse
import os
import pathlib
import time
from concurrent.futures import ThreadPoolExecutor

import towride

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENE = "scenes/default.toml"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--jobs", type=int, default=os.cpu_count())
    ap.add_argument("--png", default="out/python/hitch_variants.png")
    a = ap.parse_args()
    os.chdir(ROOT)
    variants = range(1, 11)
    t0 = time.perf_counter()
    with ThreadPoolExecutor(a.jobs) as ex:
        runs = list(ex.map(lambda v: towride.run(SCENE, set={f"{SCENE}:scene.hitch_variant": v}), variants))
    wall = time.perf_counter() - t0
    for v, r in zip(variants, runs):
        e = r.summary["channels"]["hitch_fx"]
        print(f"variant {v:2d}: hitch_fx max {e['max']:9.1f} N at {e['t_max']:.3f} s, min {e['min']:9.1f} N at {e['t_min']:.3f} s")
    print(f"{len(runs)} runs on {a.jobs} threads in {wall:.2f} s wall")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot")
        return
    fig, ax = plt.subplots(figsize=(10, 5))
    cmap = plt.get_cmap("viridis")
    for i, (v, r) in enumerate(zip(variants, runs)):
        ax.plot(r.time, r.channels["hitch_fx"] * 1e-3, color=cmap(i / 9), lw=0.9, label=f"variant {v}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"hitch_fx [k{runs[0].units['hitch_fx']}]")
    ax.set_title("Hitch force, fore-aft: ten crossbeam variants, ramp at 50 km/h")
    ax.grid(alpha=0.3)
    ax.legend(ncol=2, fontsize=8)
    png = pathlib.Path(a.png)
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
