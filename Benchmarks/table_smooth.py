#!/usr/bin/python3
"""Tables of the smooth and filleted shapes (issue 39) from BenchQuality.

Usage: /usr/bin/python3 Benchmarks/table_smooth.py [--docs DIR] PREFIX [PREFIX ...]

Reads PREFIX_normals.csv and PREFIX_features.csv of BenchQuality runs on
the shapes without a sharp edge (torus, torus2, ball, ellipsoid,
ellipsoid2, blobs, fillet2 ... fillet12, and the rounded prisms prism6r6,
prism6r10, prism8r6, prism8r10, prism12r6), averages over seeds and replaces
the text between <!-- BEGIN SMOOTH --> and <!-- END SMOOTH --> in
DIR/quality.md. Per shape, size and noise level: feature length per 1000
surfels, mean and 95th percentile of the angle to the true normal, and the
share of surfels whose normal is 10 degrees or more worse than the program's
own input (II r = 4), for the input, AT alone (--plain), the program's
default and VTK's pipeline. Standard library only.
"""
import argparse
import csv
import math
import os
from collections import defaultdict

BEGIN, END = "<!-- BEGIN SMOOTH -->", "<!-- END SMOOTH -->"
SHAPES = ["torus", "torus2", "ball", "ellipsoid", "ellipsoid2", "blobs",
          "fillet2", "fillet4", "fillet6", "fillet8", "fillet10", "fillet12",
          "prism6r6", "prism6r10", "prism8r6", "prism8r10", "prism12r6"]
METHODS = [("II-r4", "II r = 4 (input)"), ("program-plain", "AT alone (`--plain`)"),
           ("program", "program (default)"), ("VTK", "VTK pipeline"),
           ("VTK-strong", "VTK, tuned for noise")]


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return math.nan


def avg(values):
    v = [x for x in values if not math.isnan(x)]
    return sum(v) / len(v) if v else math.nan


def fmt(x, digits=1):
    return "–" if math.isnan(x) else f"{x:.{digits}f}"


def load(prefixes):
    normals = defaultdict(list)  # (shape, n, k, method, region, stat) -> values over seeds
    features = defaultdict(list)  # (shape, n, k, method) -> length per 1000 surfels
    surfels = {}
    for prefix in prefixes:
        with open(f"{prefix}_normals.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        for r in rows:
            key = (r["shape"], int(r["n"]), float(r["k"]), r["method"], r["region"])
            normals[key + ("mean",)].append(num(r["mean"]))
            normals[key + ("p95",)].append(num(r["p95"]))
            if r["method"] == "II-r4" and r["region"] == "all":
                surfels[(r["shape"], int(r["n"]), float(r["k"]), r["seed"])] = num(r["count"])
        with open(f"{prefix}_features.csv", newline="") as f:
            for r in csv.DictReader(f):
                count = surfels.get((r["shape"], int(r["n"]), float(r["k"]), r["seed"]), math.nan)
                features[(r["shape"], int(r["n"]), float(r["k"]), r["method"])].append(
                    1000 * num(r["length"]) / count if count else math.nan)
    return normals, features


def table(normals, features):
    cases = sorted({(s, n, k) for (s, n, k, *_rest) in normals}, key=lambda c: (
        c[1], SHAPES.index(c[0]) if c[0] in SHAPES else 99, c[2]))
    out = []
    for size in sorted({c[1] for c in cases}):
        out.append(f"\n### Smooth and filleted shapes, {size}³: lines per 1000 surfels · "
                   "mean / p95 angular error (°) · surfels ≥ 10° worse than the input (%)\n")
        out.append("| shape | k | " + " | ".join(label for _m, label in METHODS) + " |")
        out.append("|---|---|" + "---|" * len(METHODS))
        for shape, n, k in cases:
            if n != size or shape not in SHAPES:
                continue
            cells = []
            for m, _label in METHODS:
                mean = avg(normals.get((shape, n, k, m, "all", "mean"), []))
                p95 = avg(normals.get((shape, n, k, m, "all", "p95"), []))
                cell = f"{fmt(mean)} / {fmt(p95)}"
                if m != "II-r4":
                    cell = f"{fmt(avg(features.get((shape, n, k, m), [])))} · " + cell
                worse = avg(normals.get((shape, n, k, m, "worse10", "mean"), []))
                if not math.isnan(worse):
                    cell += f" · {fmt(worse, 2)} %"
                cells.append(cell)
            out.append(f"| {shape} | {k:g} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--docs", default=os.path.join(os.path.dirname(__file__), "..", "docs"))
    parser.add_argument("prefixes", nargs="+")
    args = parser.parse_args()
    normals, features = load(args.prefixes)
    path = os.path.join(args.docs, "quality.md")
    with open(path) as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{path}: no {BEGIN} ... {END} markers")
    head, rest = text.split(BEGIN, 1)
    _old, tail = rest.split(END, 1)
    with open(path, "w") as f:
        f.write(head + BEGIN + "\n" + table(normals, features) + END + tail)


if __name__ == "__main__":
    main()
