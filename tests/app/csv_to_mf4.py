"""Converts a towride text recording (CSV, `name [unit]` headers, `#` comments) into an
ASAM MDF4 file with asammdf, as a logger's software would: the accelerations in one
channel group at the recording's rate, half of them stored as integers-free float64 raw
values in mg-scaled m/s^2 with a linear conversion and half in g; a second channel group
with its own master at a tenth of the rate holding a speed in km/h. Usage:
csv_to_mf4.py IN.csv OUT.mf4 SPEED_KMH"""
import sys

import numpy as np
from asammdf import MDF, Signal

src, dst, speed = sys.argv[1], sys.argv[2], float(sys.argv[3])
lines = [l for l in open(src, encoding="utf-8") if l.strip() and not l.startswith("#")]
head = [c.strip() for c in lines[0].split(",")]
data = np.array([[float(x) for x in l.split(",")] for l in lines[1:]])
t = data[:, 0]
fast = []
for k, h in enumerate(head[1:], start=1):
    name = h.split("[")[0].strip()
    v = data[:, k]
    if k % 2:
        # Raw in 1/1000 m/s^2, physical = 0.001 * raw (a linear conversion).
        fast.append(Signal(v * 1000.0, t, name=name, unit="m/s^2",
                           conversion={"a": 0.001, "b": 0.0}))
    else:
        fast.append(Signal(v / 9.80665, t, name=name, unit="g"))
ts = t[::10]
slow = [Signal(np.full(len(ts), speed), ts, name="vehicle_speed", unit="km/h")]
mdf = MDF(version="4.10")
mdf.append(fast, comment="accelerations")
mdf.append(slow, comment="speed")
mdf.save(dst, overwrite=True)
