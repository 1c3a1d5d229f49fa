# Kendall tau of the variant ranking at 50 km/h (mean over both loads) between the
# nominal study summary (argv[1]) and perturbed runs of docs/data/robustness_subset.toml
# (argv[2:]), and the best variant of each (docs/durability.md, "Robustness").
import csv, sys, itertools
figs = ["hitch_fx abs_peak [N]", "hitch_stress_mid_span IIW damage per passage [-]",
        "hitch_stress_ball_mount IIW damage per passage [-]", "ball |F| peak / D [-]"]
def means(path, speed="50.0"):
    r = [x for x in csv.DictReader(open(path)) if x["speed_km_h"] == speed and x["status"] == "completed"]
    out = {}
    for f in figs:
        m = {}
        for v in map(str, range(1, 11)):
            w = [float(x[f]) for x in r if x["hitch_variant"] == v]
            m[v] = sum(w) / len(w) if len(w) == 2 else None
        out[f] = m
    return out
def tau(a, b):
    k = [v for v in a if a[v] is not None and b[v] is not None]
    c = d = 0
    for i, j in itertools.combinations(k, 2):
        s = (a[i] - a[j]) * (b[i] - b[j])
        c += s > 0; d += s < 0
    return (c - d) / (len(k) * (len(k) - 1) / 2)
nom = means(sys.argv[1])
for p in sys.argv[2:]:
    pert = means(p)
    for f in figs:
        best = lambda m: min((x for x in m if m[x] is not None), key=lambda x: m[x])
        print(f"{p.split('/')[-2]:>12} {f:55s} tau {tau(nom[f], pert[f]):+.3f} best nominal {best(nom[f])} perturbed {best(pert[f])}")
