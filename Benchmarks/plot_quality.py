#!/usr/bin/python3
"""Tables and plots for the quality benchmark (BenchQuality, issue 4).

Usage: /usr/bin/python3 Benchmarks/plot_quality.py [--docs DIR] PREFIX [PREFIX ...]

Reads PREFIX_normals.csv, PREFIX_features.csv and PREFIX_times.csv written by
BenchQuality, averages over seeds, writes DIR/quality_error.png,
DIR/quality_features.png, DIR/quality_issue15.png, DIR/quality_estimators.png
and DIR/quality_fig4.png (issue 19: VCM, RHT, AT on each; the VCM feature
score against vtkFeatureEdges and AT's lines), and replaces the text between the markers
<!-- BEGIN GENERATED --> and <!-- END GENERATED --> in DIR/quality.md (the
rest of the file, the hand-written notes, is kept). Needs numpy and
matplotlib only (Debian: python3-numpy, python3-matplotlib).
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

METHODS = ["trivial", "II-r3", "II-r4", "II-r8", "AT(II4)", "AT(II8)", "VCM", "AT(VCM)", "RHT", "AT(RHT)",
           "program-plain", "program", "VTK", "VTK-strong"]
FEATURE_METHODS = ["AT(II4)", "AT(II8)", "AT(VCM)", "AT(RHT)", "program-plain", "program", "VTK", "VTK-strong"]
# The paper's Fig. 5 estimators (issue 19) and AT on each.
PAPER_METHODS = ["II-r4", "AT(II4)", "VCM", "AT(VCM)", "RHT", "AT(RHT)"]
# The paper's Fig. 4 comparison (issue 19): the VCM feature score at three
# thresholds, vtkFeatureEdges on the VTK pipelines, and AT's lines.
VCM_T = ["VCM-T0.1", "VCM-T0.2", "VCM-T0.3"]
FIG4_METHODS = VCM_T + ["VTK", "VTK-strong", "AT(II4)", "AT(II8)", "AT(VCM)", "AT(RHT)", "program"]
# The methods of the first plots (issues 4 and 15).
PLOT_METHODS = ["trivial", "II-r3", "II-r4", "II-r8", "AT(II4)", "AT(II8)", "program-plain", "program",
                "VTK", "VTK-strong"]
PLOT_FEATURE_METHODS = ["AT(II4)", "AT(II8)", "program-plain", "program", "VTK", "VTK-strong"]
# Methods built on AT (the program's rows are AT followed, or not, by the
# sharp-features stage).
AT_BASED = ("AT(II4)", "AT(II8)", "AT(VCM)", "AT(RHT)", "program-plain", "program")
# Issue 15's comparison: its shapes first, then the others.
ISSUE15_METHODS = ["II-r4", "AT(II4)", "program-plain", "program", "VTK", "VTK-strong"]
ISSUE15_SHAPES = ["cube", "octahedron", "cubesphere"]
EDGE_SHAPES = ["cube", "cubesphere", "cylinder", "octahedron", "wedge"]
ALL_SHAPES = ["sphere"] + EDGE_SHAPES
BEGIN, END = "<!-- BEGIN GENERATED -->", "<!-- END GENERATED -->"


def fnum(x):
    try:
        v = float(x)
    except ValueError:
        return math.nan
    return v


def read(prefix, kind):
    path = f"{prefix}_{kind}.csv"
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def mean(values):
    v = [x for x in values if not math.isnan(x)]
    return sum(v) / len(v) if v else math.nan


def fmt(x, digits=1):
    return "–" if x is None or math.isnan(x) else f"{x:.{digits}f}"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--docs", default=os.path.join(os.path.dirname(__file__), "..", "docs"))
    ap.add_argument("prefixes", nargs="+")
    args = ap.parse_args()

    normals, features, times = [], [], []
    for p in args.prefixes:
        normals += read(p, "normals")
        features += read(p, "features")
        times += read(p, "times")

    # (shape, n, k, method, region) -> {stat: [per-seed values]}
    err = defaultdict(lambda: defaultdict(list))
    for r in normals:
        key = (r["shape"], int(r["n"]), float(r["k"]), r["method"], r["region"])
        for s in ("mean", "median", "p95"):
            err[key][s].append(fnum(r[s]))
        err[key]["count"].append(fnum(r["count"]))
    feat = defaultdict(lambda: defaultdict(list))
    for r in features:
        key = (r["shape"], int(r["n"]), float(r["k"]), r["method"])
        for s in ("length", "precision", "recall", "f1", "iterations", "multiplicity", "offset"):
            feat[key][s].append(fnum(r.get(s, "nan")))
    tim = defaultdict(list)
    cells = defaultdict(list)
    for r in times:
        tim[(int(r["n"]), float(r["k"]), r["stage"])].append(fnum(r["seconds"]))
        cells[(int(r["n"]), float(r["k"]), r["stage"])].append(fnum(r["cells"]))

    sizes = sorted({k[1] for k in err})
    noise = {n: sorted({k[2] for k in err if k[1] == n}) for n in sizes}
    shapes_present = [s for s in ALL_SHAPES if any(k[0] == s for k in err)]
    edge_shapes = [s for s in EDGE_SHAPES if s in shapes_present]
    seeds = defaultdict(set)
    for r in normals:
        seeds[(int(r["n"]), float(r["k"]))].add(int(r["seed"]))

    def E(shape, n, k, m, region, stat="mean"):
        v = err.get((shape, n, k, m, region))
        return mean(v[stat]) if v else math.nan

    def Eavg(shapes, n, k, m, region, stat="mean"):
        return mean([E(s, n, k, m, region, stat) for s in shapes])

    def Fs(shape, n, k, m, stat):
        v = feat.get((shape, n, k, m))
        return mean(v[stat]) if v else math.nan

    def Favg(shapes, n, k, m, stat):
        return mean([Fs(s, n, k, m, stat) for s in shapes])

    out = []
    w = out.append
    main_n = sizes[0]
    ks = noise[main_n]
    w(f"Generated by `Benchmarks/plot_quality.py` from {', '.join(os.path.basename(p) + '_*.csv' for p in args.prefixes)}. "
      f"Errors in degrees; each figure is averaged over seeds first, then over shapes. "
      f"Seeds per case: " + "; ".join(
          f"{n}³: " + ", ".join(f"k={k:g}: {len(seeds[(n, k)])}" for k in noise[n]) for n in sizes) + ".")
    w("")
    # Averages over shapes, one set of tables per size.
    for main_n in sizes:
        ks = noise[main_n]
        for region, title in (("near", "near sharp edges (≤ 2 voxels)"), ("away", "away from sharp edges")):
            w(f"### Mean angular error {title}, {main_n}³, average over {', '.join(edge_shapes)}")
            w("")
            w("| method | " + " | ".join(f"k={k:g}" for k in ks) + " |")
            w("|---|" + "---:|" * len(ks))
            for m in METHODS:
                vals = [Eavg(edge_shapes, main_n, k, m, region) for k in ks]
                best = [min(Eavg(edge_shapes, main_n, k, mm, region) for mm in METHODS) for k in ks]
                cells_ = [("**" + fmt(v) + "**") if abs(v - b) < 1e-9 else fmt(v) for v, b in zip(vals, best)]
                w(f"| {m} | " + " | ".join(cells_) + " |")
            w("")
        if "sphere" in shapes_present:
            w(f"### Sphere (no sharp edge), {main_n}³: mean / 95th percentile angular error")
            w("")
            w("| method | " + " | ".join(f"k={k:g}" for k in ks) + " |")
            w("|---|" + "---:|" * len(ks))
            for m in METHODS:
                w(f"| {m} | " + " | ".join(
                    fmt(E("sphere", main_n, k, m, "all")) + " / " + fmt(E("sphere", main_n, k, m, "all", "p95"))
                    for k in ks) + " |")
            w("")
        kk = [k for k in ks if k in (0.0, 0.3, 0.5)]
        w(f"### Mean error by distance d to the nearest sharp edge, {main_n}³: near (d ≤ 2) / mid (2 < d ≤ 8) / far (d > 8)")
        w("")
        w("The II r = 8 ball reaches across an edge up to d = 8: 'mid' is where a piecewise-smooth "
          "reconstruction should beat II r = 8, 'far' is plain smooth surface.")
        w("")
        w("| method | " + " | ".join(f"k={k:g}" for k in kk) + " |")
        w("|---|" + "---:|" * len(kk))
        for m in METHODS:
            w(f"| {m} | " + " | ".join(" / ".join(fmt(Eavg(edge_shapes, main_n, k, m, reg)) for reg in ("near", "mid", "far"))
                                       for k in kk) + " |")
        w("")
        w(f"### Median and 95th percentile near edges, {main_n}³ (median / p95, average over shapes with edges)")
        w("")
        w("| method | " + " | ".join(f"k={k:g}" for k in ks) + " |")
        w("|---|" + "---:|" * len(ks))
        for m in METHODS:
            w(f"| {m} | " + " | ".join(
                fmt(Eavg(edge_shapes, main_n, k, m, "near", "median")) + " / " +
                fmt(Eavg(edge_shapes, main_n, k, m, "near", "p95")) for k in ks) + " |")
        w("")
        w(f"### Feature edges, {main_n}³: precision / recall / F1 (precision by length; average over shapes with edges)")
        w("")
        w("| method | " + " | ".join(f"k={k:g}" for k in ks) + " |")
        w("|---|" + "---:|" * len(ks))
        for m in FEATURE_METHODS:
            w(f"| {m} | " + " | ".join(
                fmt(Favg(edge_shapes, main_n, k, m, "precision"), 2) + " / " +
                fmt(Favg(edge_shapes, main_n, k, m, "recall"), 2) + " / " +
                fmt(Favg(edge_shapes, main_n, k, m, "f1"), 2) for k in ks) + " |")
        if "sphere" in shapes_present:
            w("| false edge length on the sphere (voxels): |" + " |" * len(ks))
            for m in FEATURE_METHODS:
                w(f"| {m} | " + " | ".join(fmt(Fs("sphere", main_n, k, m, "length"), 0) for k in ks) + " |")
        w("")

    # Issue 15's metrics (Testing/Cxx/dgFeatureMetrics.h): summary over its
    # shapes, then every shape; k = 0, 0.3, 0.5.
    i15_shapes = [s for s in ISSUE15_SHAPES if s in shapes_present]

    def mm(shape, n, k, m, region):
        return fmt(E(shape, n, k, m, region)) + " (" + fmt(E(shape, n, k, m, region, "median")) + ")"

    def i15_cells(shapes, n, k, m):
        def avg(f):
            # A mean over the shapes that have the figure; '*' when some
            # have not (VTK-strong: no triangle centre within the band).
            v = [f(s) for s in shapes]
            missing = sum(math.isnan(x) for x in v)
            return mean(v), "*" if 0 < missing < len(v) else ""

        def cell(x, digits=2):
            return fmt(x[0], digits) + x[1]

        c = [cell(avg(lambda s: Fs(s, n, k, m, stat))) for stat in ("multiplicity", "offset", "precision", "recall")]
        for region in ("surface2", "edge1", "edge3"):
            c.append(cell(avg(lambda s: E(s, n, k, m, region)), 1) + " (" +
                     cell(avg(lambda s: E(s, n, k, m, region, "median")), 1) + ")")
        return c

    header = ("| mult. | offset | precision | recall | error, all (median) | "
              "≤ 1 voxel of an edge (median) | ≤ 3 voxels (median) |")
    for n in sizes:
        kk = [k for k in noise[n] if k in (0.0, 0.3, 0.5)]
        if i15_shapes:
            w(f"### Issue 15's metrics, {n}³: mean over {', '.join(i15_shapes)}")
            w("")
            w("Errors in degrees, mean (median) over the cells, then averaged over the shapes; "
              "'*': the mean of the shapes that have the figure (the others have no cell in that region, "
              "or no line near an edge for the offset).")
            w("")
            w("| k | method " + header)
            w("|---:|---|" + "---:|" * 7)
            for k in kk:
                for m in ISSUE15_METHODS:
                    w(f"| {k:g} | {m} | " + " | ".join(i15_cells(i15_shapes, n, k, m)) + " |")
            w("")
        w(f"### Issue 15's metrics per shape, {n}³")
        w("")
        w("| shape | k | method " + header)
        w("|---|---:|---|" + "---:|" * 7)
        order = i15_shapes + [s for s in shapes_present if s not in i15_shapes]
        for s in order:
            for k in kk:
                for m in ISSUE15_METHODS:
                    w(f"| {s} | {k:g} | {m} | " + " | ".join(i15_cells([s], n, k, m)) + " |")
        w("")

    # Issue 19: the paper's other estimators (Fig. 5) and the feature
    # comparison (Fig. 4), per size.
    for n in sizes:
        kk = [k for k in noise[n] if k in (0.0, 0.3, 0.5)]
        w(f"### The paper's estimators and AT on each, {n}³: near (d ≤ 2) / mid (2 < d ≤ 8) / far (d > 8); ≤ 1 voxel of an edge; all within 2 voxels of the surface")
        w("")
        w("Mean error (degrees) over the shapes with edges. 'near / mid / far' count every surfel, noise "
          "islands included; '≤ 1' and 'surf.' are issue 15's unoriented errors on the surfels within 2 voxels "
          "of the true surface (most islands drop out): within 1 voxel of an edge, and all of them. "
          "Sphere: all surfels / issue 15's 'surf.'.")
        w("")
        w("| method | " + " | ".join(f"k={k:g} near / mid / far; ≤ 1; surf." for k in kk) + " | " +
          " | ".join(f"sphere k={k:g}" for k in kk) + " |")
        w("|---|" + "---:|" * (2 * len(kk)))
        for m in PAPER_METHODS:
            w(f"| {m} | " + " | ".join(
                " / ".join(fmt(Eavg(edge_shapes, n, k, m, reg)) for reg in ("near", "mid", "far")) + "; " +
                fmt(Eavg(edge_shapes, n, k, m, "edge1")) + "; " + fmt(Eavg(edge_shapes, n, k, m, "surface2"))
                for k in kk) + " | " +
              " | ".join(fmt(E("sphere", n, k, m, "all")) + " / " + fmt(E("sphere", n, k, m, "surface2"))
                         for k in kk) + " |")
        w("")
        w(f"### Per shape, {n}³: the paper's estimators, mean error near / away, F1 of AT's lines")
        w("")
        w("| shape | k | " + " | ".join(PAPER_METHODS) + " | F1 AT(II4) | F1 AT(VCM) | F1 AT(RHT) |")
        w("|---|---:|" + "---:|" * (len(PAPER_METHODS) + 3))
        for s in shapes_present:
            for k in noise[n]:
                row = [fmt(E(s, n, k, m, "near")) + " / " + fmt(E(s, n, k, m, "away")) for m in PAPER_METHODS]
                row += [fmt(Fs(s, n, k, m, "f1"), 2) for m in ("AT(II4)", "AT(VCM)", "AT(RHT)")]
                w(f"| {s} | {k:g} | " + " | ".join(row) + " |")
        w("")
        w(f"### Feature detection (paper Fig. 4), {n}³: precision / recall / F1, mean over the shapes with edges")
        w("")
        w("VCM-T*: the edges whose surfels all have VCMFeatureScore ≥ T (VCM R = 10, r = 4); VTK, VTK-strong: "
          "vtkFeatureEdges (30°) on the smoothed meshes; AT(…): AT's lines (v < 0.5 at both ends); program: "
          "the sharp-features stage's lines. Multiplicity in brackets (detected length near an edge over the "
          "true length: 1–1.7 is one line).")
        w("")
        w("| method | " + " | ".join(f"k={k:g}" for k in noise[n]) + " |")
        w("|---|" + "---:|" * len(noise[n]))
        for m in FIG4_METHODS:
            w(f"| {m} | " + " | ".join(
                fmt(Favg(edge_shapes, n, k, m, "precision"), 2) + " / " +
                fmt(Favg(edge_shapes, n, k, m, "recall"), 2) + " / " +
                fmt(Favg(edge_shapes, n, k, m, "f1"), 2) + " (" +
                fmt(Favg(edge_shapes, n, k, m, "multiplicity"), 1) + ")" for k in noise[n]) + " |")
        if "sphere" in shapes_present:
            w("| false length on the sphere (voxels): |" + " |" * len(noise[n]))
            for m in FIG4_METHODS:
                w(f"| {m} | " + " | ".join(fmt(Fs("sphere", n, k, m, "length"), 0) for k in noise[n]) + " |")
        w("")
        w(f"### Feature detection per shape, {n}³: precision / recall")
        w("")
        w("| shape | k | " + " | ".join(FIG4_METHODS) + " |")
        w("|---|---:|" + "---:|" * len(FIG4_METHODS))
        for s in edge_shapes:
            for k in noise[n]:
                w(f"| {s} | {k:g} | " + " | ".join(
                    fmt(Fs(s, n, k, m, "precision"), 2) + " / " + fmt(Fs(s, n, k, m, "recall"), 2)
                    for m in FIG4_METHODS) + " |")
        w("")

    # Per shape, per size, every k: mean near / away and F1 for the main methods.
    for n in sizes:
        w(f"### Per shape, {n}³: mean error near / away, feature F1")
        w("")
        cols = ["II-r4", "II-r8", "AT(II4)", "AT(II8)", "program", "VTK", "VTK-strong"]
        fcols = ["AT(II4)", "AT(II8)", "program", "VTK", "VTK-strong"]
        w("| shape | k | " + " | ".join(cols) + " | " + " | ".join(f"F1 {m}" for m in fcols) + " |")
        w("|---|---:|" + "---:|" * (len(cols) + len(fcols)))
        for s in shapes_present:
            for k in noise[n]:
                row = [fmt(E(s, n, k, m, "near")) + " / " + fmt(E(s, n, k, m, "away")) for m in cols]
                row += [fmt(Fs(s, n, k, m, "f1"), 2) for m in fcols]
                w(f"| {s} | {k:g} | " + " | ".join(row) + " |")
        w("")

    # The expected outcome, checked case by case.
    w("### Expected outcome, checked: best method per case for k ≥ 0.2")
    w("")
    w("Lowest mean error near edges, lowest away, best F1 (ties to the first listed). "
      "'AT-based' = AT(II4), AT(II8), AT(VCM), AT(RHT), program-plain or program.")
    w("")
    w("| n | shape | k | best near | best away | best F1 |")
    w("|---:|---|---:|---|---|---|")
    wins = {"near": [0, 0], "away": [0, 0], "f1": [0, 0]}
    prog = {"near": 0, "away": 0, "f1": 0}
    for n in sizes:
        for s in shapes_present:
            for k in noise[n]:
                if k < 0.2:
                    continue
                bn = min(METHODS, key=lambda m: (lambda v: math.inf if math.isnan(v) else v)(E(s, n, k, m, "near")))
                ba = min(METHODS, key=lambda m: (lambda v: math.inf if math.isnan(v) else v)(E(s, n, k, m, "away")))
                bf = max(FEATURE_METHODS, key=lambda m: (lambda v: -1 if math.isnan(v) else v)(Fs(s, n, k, m, "f1")))
                has_edges = s != "sphere"
                bn_txt = bn if has_edges else "–"
                bf_txt = bf if has_edges else "–"
                if has_edges:
                    wins["near"][0] += bn in AT_BASED
                    wins["near"][1] += 1
                    wins["f1"][0] += bf in AT_BASED
                    wins["f1"][1] += 1
                    prog["near"] += bn == "program"
                    prog["f1"] += bf == "program"
                wins["away"][0] += ba in AT_BASED
                wins["away"][1] += 1
                prog["away"] += ba == "program"
                w(f"| {n} | {s} | {k:g} | {bn_txt} | {ba} | {bf_txt} |")
    w("")
    w(f"An AT-based method is best near edges in {wins['near'][0]}/{wins['near'][1]} cases "
      f"(the program in {prog['near']}), away from edges in {wins['away'][0]}/{wins['away'][1]} "
      f"(the program in {prog['away']}), and has the best F1 in {wins['f1'][0]}/{wins['f1'][1]} "
      f"(the program in {prog['f1']}).")
    w("")

    # Times.
    w("### Time per stage (seconds, mean over shapes and seeds; 2 cores, STDThread)")
    w("")
    stages = []
    for r in times:
        if r["stage"] not in stages:
            stages.append(r["stage"])
    tk = [(n, k) for n in sizes for k in noise[n] if k in (0.0, 0.3, 0.5)]
    w("| stage | " + " | ".join(f"{n}³ k={k:g}" for n, k in tk) + " |")
    w("|---|" + "---:|" * len(tk))
    for st in stages:
        if st == "noise":
            continue
        w(f"| {st} | " + " | ".join(fmt(mean(tim.get((n, k, st), [])), 2) for n, k in tk) + " |")
    w("| surfels (digital surface) | " + " | ".join(
        fmt(mean(cells.get((n, k, "digital surface"), [])), 0) for n, k in tk) + " |")
    w("| triangles (VTK) | " + " | ".join(
        fmt(mean(cells.get((n, k, "VTK flying edges"), [])), 0) for n, k in tk) + " |")
    w("| surfels (program, islands removed) | " + " | ".join(
        fmt(mean(cells.get((n, k, "program digital surface"), [])), 0) for n, k in tk) + " |")
    w("| AT(II4) / AT(II8) / AT(VCM) / AT(RHT) / program iterations | " + " | ".join(
        " / ".join(fmt(mean([x for s in shapes_present for x in feat.get((s, n, k, m), {}).get("iterations", [])]), 0)
                   for m in ("AT(II4)", "AT(II8)", "AT(VCM)", "AT(RHT)", "program"))
        for n, k in tk) + " |")
    w("")

    # Plots: the smallest size, which has the most seeds per case.
    main_n = sizes[0]
    ks = noise[main_n]
    styles = {"trivial": ("0.6", ":"), "II-r3": ("tab:olive", "--"), "II-r4": ("tab:green", "--"),
              "II-r8": ("tab:cyan", "--"), "AT(II4)": ("tab:red", "-"), "AT(II8)": ("tab:purple", "-"),
              "program-plain": ("tab:brown", "-"), "program": ("black", "-"),
              "VTK": ("tab:blue", "-."), "VTK-strong": ("tab:orange", "-."),
              "VCM": ("tab:pink", "--"), "AT(VCM)": ("tab:pink", "-"), "RHT": ("tab:gray", "--"),
              "AT(RHT)": ("tab:gray", "-"), "VCM-T0.1": ("tab:pink", ":"), "VCM-T0.2": ("darkmagenta", ":"),
              "VCM-T0.3": ("indigo", ":")}
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), dpi=80)
    panels = [("near", edge_shapes, "near sharp edges"), ("away", edge_shapes, "away from edges")]
    if "sphere" in shapes_present:
        panels.append(("all", ["sphere"], "sphere"))
    for ax, (region, shp, title) in zip(axes, panels):
        for m in PLOT_METHODS:
            c, ls = styles[m]
            ax.plot(ks, [Eavg(shp, main_n, k, m, region) for k in ks], ls, color=c, marker=".", label=m)
        ax.set_title(f"{title} ({main_n}³)", fontsize=10)
        ax.set_xlabel("noise k")
        ax.set_yscale("log")
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_yticks([0.5, 1, 2, 5, 10, 20, 50, 100])
        ax.grid(True, which="both", alpha=0.3)
    for ax in axes[len(panels):]:
        ax.set_visible(False)
    axes[0].set_ylabel("mean angular error (deg)")
    axes[len(panels) - 1].legend(fontsize=7, loc="lower right", ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(args.docs, "quality_error.png"))
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(11, 3.2), dpi=80)
    for ax, stat in zip(axes, ("precision", "recall", "f1")):
        for m in PLOT_FEATURE_METHODS:
            c, ls = styles[m]
            ax.plot(ks, [Favg(edge_shapes, main_n, k, m, stat) for k in ks], ls, color=c, marker=".", label=m)
        ax.set_title(f"feature {stat} ({main_n}³, shapes with edges)", fontsize=10)
        ax.set_xlabel("noise k")
        ax.set_ylim(0, 1.02)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.docs, "quality_features.png"))
    plt.close(fig)

    i15_shapes = [s for s in ISSUE15_SHAPES if s in shapes_present]
    if i15_shapes:
        fig, axes = plt.subplots(1, 4, figsize=(13, 3.2), dpi=80)
        panels = [(("feature", "multiplicity"), "multiplicity"), (("feature", "precision"), "precision"),
                  (("feature", "recall"), "recall"), (("normal", "edge1"), "mean error ≤ 1 voxel of an edge (deg)")]
        for ax, ((kind, stat), title) in zip(axes, panels):
            for m in ISSUE15_METHODS:
                if kind == "feature" and m not in PLOT_FEATURE_METHODS:
                    continue
                c, ls = styles[m]
                ys = [Favg(i15_shapes, main_n, k, m, stat) if kind == "feature" else Eavg(i15_shapes, main_n, k, m, stat)
                      for k in ks]
                ax.plot(ks, ys, ls, color=c, marker=".", label=m)
            ax.set_title(f"{title} ({main_n}³)", fontsize=9)
            ax.set_xlabel("noise k")
            if stat in ("precision", "recall"):
                ax.set_ylim(0, 1.02)
            if stat == "multiplicity":
                ax.set_yscale("log")
                ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
                ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
                ax.set_yticks([0.1, 0.2, 0.5, 1, 2, 5, 10, 20])
                ax.set_ylim(0.05, 25)
            ax.grid(True, which="both", alpha=0.3)
        axes[-1].legend(fontsize=7)
        fig.suptitle(f"issue 15's metrics, mean over {', '.join(i15_shapes)}", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(args.docs, "quality_issue15.png"))
        plt.close(fig)

    # Issue 19: the paper's estimators (near, away, sphere) and the feature
    # comparison (precision, recall, F1), one row per size.
    fig, axes = plt.subplots(len(sizes), 3, figsize=(11, 3.2 * len(sizes)), dpi=80, squeeze=False)
    for row, n in zip(axes, sizes):
        kn = noise[n]
        panels = [("near", edge_shapes, "near sharp edges"), ("far", edge_shapes, "far from edges (d > 8)"),
                  ("all", ["sphere"], "sphere")]
        for ax, (region, shp, title) in zip(row, panels):
            for m in PAPER_METHODS:
                c, ls = styles[m]
                ax.plot(kn, [Eavg(shp, n, k, m, region) for k in kn], ls, color=c, marker=".", label=m)
            ax.set_title(f"{title} ({n}³)", fontsize=10)
            ax.set_xlabel("noise k")
            ax.set_yscale("log")
            ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
            ax.set_yticks([0.5, 1, 2, 5, 10, 20, 50])
            ax.grid(True, which="both", alpha=0.3)
        row[0].set_ylabel("mean angular error (deg)")
    axes[0][2].legend(fontsize=7, loc="upper left", ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(args.docs, "quality_estimators.png"))
    plt.close(fig)

    fig, axes = plt.subplots(len(sizes), 3, figsize=(11, 3.2 * len(sizes)), dpi=80, squeeze=False)
    for row, n in zip(axes, sizes):
        kn = noise[n]
        for ax, stat in zip(row, ("precision", "recall", "f1")):
            for m in FIG4_METHODS:
                c, ls = styles[m]
                ax.plot(kn, [Favg(edge_shapes, n, k, m, stat) for k in kn], ls, color=c, marker=".", label=m)
            ax.set_title(f"feature {stat} ({n}³, shapes with edges)", fontsize=10)
            ax.set_xlabel("noise k")
            ax.set_ylim(0, 1.02)
            ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(args.docs, "quality_fig4.png"))
    plt.close(fig)

    md = os.path.join(args.docs, "quality.md")
    text = open(md).read() if os.path.exists(md) else f"# Quality benchmark\n\n{BEGIN}\n{END}\n"
    if BEGIN not in text or END not in text:
        text += f"\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(md, "w") as f:
        f.write(head + BEGIN + "\n" + "\n".join(out) + "\n" + END + tail)
    print(f"wrote {md}, quality_error.png, quality_features.png, quality_issue15.png, "
          f"quality_estimators.png, quality_fig4.png in {args.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
