#!/usr/bin/python3
"""The whole program on the real pipeline, as issue 16 times it: read ->
surface -> II r = 3 -> AT (the paper's parameters) -> write, no picture.

    /usr/bin/python3 Benchmarks/bench_program.py [--runs 3] [--program PATH]
        [VOLUME ...] [-- extra program options]

VOLUME: a name under ../shared/data/volgallery (default octa-flower17k-512)
or a path. Prints the program's own stage times and the process's wall time
for every run, then their medians, with the machine and its load.
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GALLERY = os.path.join(ROOT, "..", "shared", "data", "volgallery")
PIPELINE = ["--radius", "3", "--alpha", "0.1", "--lambda", "0.01", "--plain",
            "--no-png", "--min-component", "0", "--quiet"]
STAGES = ["read", "digital surface", "II normals", "Ambrosio-Tortorelli", "write", "total"]


def stage_times(text):
    line = next((l for l in text.splitlines() if l.strip().startswith("time:")), None)
    if line is None:
        return None
    out = {}
    for name in STAGES:
        m = re.search(re.escape(name) + r" ([0-9.]+) s", line)
        if m:
            out[name] = float(m.group(1))
    return out


def main(argv):
    runs, program, volumes, extra = 3, os.path.join(ROOT, "build", "bin", "piecewise-normals"), [], []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    i = 0
    while i < len(argv):
        if argv[i] == "--runs":
            runs = int(argv[i + 1])
            i += 2
        elif argv[i] == "--program":
            program = argv[i + 1]
            i += 2
        else:
            volumes.append(argv[i])
            i += 1
    volumes = volumes or ["octa-flower17k-512"]
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    print(f"bench_program: {program}, {runs} runs, options {' '.join(PIPELINE + extra)}")
    print(f"machine: {os.uname().nodename}, nproc {os.cpu_count()}, {cpu}; "
          f"loadavg at start {os.getloadavg()[0]:.2f}")
    status = 0
    for vol in volumes:
        path = vol if os.path.exists(vol) else os.path.join(GALLERY, vol + ".vol")
        if not os.path.exists(path):
            print(f"{vol}: {path} not found, skipped")
            continue
        rows = []
        for r in range(runs):
            with tempfile.TemporaryDirectory() as out:
                t0 = time.perf_counter()
                p = subprocess.run([program, path, "--output-dir", out] + PIPELINE + extra,
                                   capture_output=True, text=True)
                wall = time.perf_counter() - t0
            times = stage_times(p.stdout)
            if p.returncode != 0 or times is None:
                print(f"{vol}: run {r + 1} failed (exit {p.returncode}):\n{p.stdout}{p.stderr}")
                status = 1
                break
            times["process wall"] = wall
            rows.append(times)
            print(f"{vol} run {r + 1}: " + ", ".join(f"{k} {v:.3f} s" for k, v in times.items()))
        if rows:
            keys = list(rows[0].keys())
            print(f"{vol} median of {len(rows)}: " +
                  ", ".join(f"{k} {statistics.median(t[k] for t in rows):.3f} s" for k in keys))
    print(f"loadavg at end {os.getloadavg()[0]:.2f}")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
