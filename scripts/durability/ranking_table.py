#!/usr/bin/env python3
"""The braking rankings' table of docs/durability.md from two `towride sweep rank --json`
documents (over the ramp and on the flat road), figure by figure: the best variant, the
means of variants 1, 5 and 10 over the band, and the largest spread (max - min over the
band, over the mean) of any variant.

    towride sweep rank RAMP/summary.csv --figures "$(cat FIGURES)" --json > ramp.json
    towride sweep rank FLAT/summary.csv --figures "$(cat FIGURES)" --json > flat.json
    python3 scripts/durability/ranking_table.py ramp.json flat.json
"""
import json
import sys


def fmt(x):
    return f"{x:.4g}"


def columns(fig):
    by = {e["value"]: e for e in fig["entries"]}
    best = min(fig["entries"], key=lambda e: e["rank"])["value"]
    spread = max((e["max"] - e["min"]) / abs(e["mean"]) for e in fig["entries"] if e["mean"])
    return [best] + [fmt(by[v]["mean"]) for v in ("1", "5", "10")] + [f"{100 * spread:.0f} %"]


def main():
    ramp, flat = (json.load(open(p)) for p in sys.argv[1:3])
    flat_by = {f["figure"]: f for f in flat["figures"]}
    print("| figure | ramp: best | 1 | 5 | 10 | spread | flat: best | 1 | 5 | 10 | spread |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for f in ramp["figures"]:
        name = f["figure"].replace("abs_peak", "\\|peak\\|")
        row = columns(f) + columns(flat_by[f["figure"]])
        print(f"| {name} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
