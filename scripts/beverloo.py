#!/usr/bin/env python3
"""Discharge of a flat-bottomed 2D silo against Beverloo's law, W = C (D - k d)^n.

For each orifice width D (in grain diameters d), writes a scene: a silo 8 wide whose floor is two
fixed blocky planks (exponent 50, 0.4 thick) either side of the orifice, filled with 3,800 disks
of diameter 0.18-0.22 (d = 0.2) placed on a loose lattice, and a sink under the orifice. Runs it
with `supergrain run` with the discharge measured every `--chunk` steps (`run --measure discharge
--measures DIR`: the grains the sink has taken and those still in the box, which the script
checks add up to all that appeared), and takes the rate as a least-squares line through the
counts while more than `--full` grains remain in the box (a fill at least as high as the silo is
wide, where the rate should not depend on it) and after the first row past the start (the
lattice settling). Then fits C, k and n together (k on a fine grid, C and n by
a log-log line at each k) and prints the table and the fit.

Usage: scripts/beverloo.py [--bin PATH] [--widths 5,6,8,10,12,15] [--out DIR]
Needs only Python 3 and a built `supergrain` (cargo build --release -p supergrain-cli).
"""

import argparse
import json
import math
import os
import random
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

D_GRAIN = 0.2  # mean diameter
STEP = 0.005
GRAINS = 3800  # in a silo 8 wide; as many more as a wider silo is wider


def scene(nd: float, silo: float = 8.0, seed: int = 0) -> str:
    width = nd * D_GRAIN
    w2 = silo / 2
    half = (w2 - width / 2) / 2
    # Seed 0 draws the radii as this script always has; others draw their own.
    rng = random.Random(int(nd * 100) + 100003 * seed)
    grains_total = round(GRAINS * silo / 8.0)
    spacing = 0.23
    cols = int((silo - 0.2) / spacing)
    x0 = -w2 + (silo - (cols - 1) * spacing) / 2
    y = 2.2 + spacing / 2 + 0.01
    grains = []
    while len(grains) < grains_total:
        for c in range(cols):
            if len(grains) == grains_total:
                break
            grains.append((x0 + c * spacing, y, rng.uniform(0.09, 0.11)))
        y += spacing
    text = f"""# A flat-bottomed silo {silo:g} wide (scripts/beverloo.py): planks 0.4 thick either side of an
# orifice {nd:g} grain diameters wide (D = {width:.2f}), {grains_total} disks of diameter 0.18-0.22
# placed on a lattice, a sink under the orifice.
seed = 1

[box]
left = {-w2}
right = {w2}
floor = 0.0
top = {y + 1.0:.3f}

[solver]
model = "soft"
step = {STEP}

[[grain]]
center = [{-w2 + half}, 2.0]
semi_axes = [{half}, 0.2]
exponent = 50.0
fixed = true

[[grain]]
center = [{w2 - half}, 2.0]
semi_axes = [{half}, 0.2]
exponent = 50.0
fixed = true

[[sink]]
region = [[{-w2}, {w2}], [0.0, 1.0]]
"""
    for x, yy, r in grains:
        text += f"\n[[grain]]\ncenter = [{x:.4f}, {yy:.4f}]\nradius = {r:.4f}\n"
    return text


def run(binary: str, out: str, nd: float, chunk: int, chunks: int, silo: float, seed: int):
    """Runs the silo of `nd` diameters with the discharge measured every `chunk` steps; returns
    its rows as (step, grains taken, grains in the box)."""
    path = os.path.join(out, f"silo{nd:g}.toml")
    with open(path, "w") as f:
        f.write(scene(nd, silo, seed))
    measures = os.path.join(out, f"silo{nd:g}")
    cmd = [binary, "--threads", "1", "run", path, "--steps", str(chunk * chunks),
           "--measure", "discharge", "--every", str(chunk), "--measures", measures, "-q"]
    subprocess.run(cmd, check=True)
    rows = []
    with open(os.path.join(measures, "discharge.csv")) as f:
        next(f)
        for line_ in f:
            step, _, _, grains, _, in_box, appeared = line_.strip().split(",")
            assert int(appeared) == int(in_box) + int(grains), line_
            rows.append((int(step), int(grains), int(in_box)))
    return nd, rows


def line(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    slope = sxy / sxx
    return slope, my - slope * mx


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(here, "..", "target", "release", "supergrain"))
    ap.add_argument("--widths", default="5,6,8,10,12,15")
    ap.add_argument("--out", default="beverloo-out")
    ap.add_argument("--chunk", type=int, default=200)
    ap.add_argument("--full", type=int, default=None,
                    help="fit while more grains than this are in the box (default: 1,700 in a "
                    "silo 8 wide, as many more as the fill of a wider silo must be higher)")
    ap.add_argument("--silo", type=float, default=8.0,
                    help="the silo's width (8: 40 grain diameters); its grains grow with it")
    ap.add_argument("--seed", type=int, default=0,
                    help="which draw of the grains' radii (0: the script's first)")
    ap.add_argument("--chunks", type=int, default=40)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--scene-only", type=float, metavar="D",
                    help="write the scene of an orifice D grain diameters wide into --out, and stop")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.scene_only is not None:
        path = os.path.join(a.out, f"silo{a.scene_only:g}.toml")
        with open(path, "w") as f:
            f.write(scene(a.scene_only, a.silo, a.seed))
        print(path)
        return 0
    if a.full is None:
        a.full = round(1700 * (a.silo / 8.0) ** 2)
    widths = [float(w) for w in a.widths.split(",")]
    with ThreadPoolExecutor(a.jobs) as pool:
        results = list(pool.map(lambda nd: run(a.bin, a.out, nd, a.chunk, a.chunks, a.silo, a.seed), widths))
    table = []
    print("D/d   rate (grains/s)   points   counts (step, taken, in the box)")
    for nd, rows in results:
        window = [(s, t) for s, t, in_box in rows[2:] if in_box > a.full]
        if len(window) < 2:
            print(f"{nd:4g}   jammed or too short: {rows}")
            continue
        slope, _ = line([s * STEP for s, _ in window], [t for _, t in window])
        table.append((nd, slope))
        print(f"{nd:4g}   {slope:10.1f}        {len(window):3d}      {rows}")
    if len(table) < 3:
        print("too few widths flowed to fit")
        return 1
    # W = C (D - k d)^n, D and d in grain diameters: k on a grid, n and C by a log-log line.
    best = None
    for i in range(0, 400):
        k = i * 0.01
        if any(nd - k <= 0 for nd, _ in table):
            break
        xs = [math.log(nd - k) for nd, _ in table]
        ys = [math.log(w) for _, w in table]
        n, lc = line(xs, ys)
        err = sum((y - (lc + n * x)) ** 2 for x, y in zip(xs, ys))
        if best is None or err < best[0]:
            best = (err, k, n, math.exp(lc))
    err, k, n, c = best
    print(f"fit: W = C (D - k d)^n with C = {c:.2f} grains/s, k = {k:.2f}, n = {n:.3f} "
          f"(residual {err:.2e} in log W)")
    # And with n held at 3/2: C and k.
    best15 = None
    for i in range(0, 400):
        k15 = i * 0.01
        if any(nd - k15 <= 0 for nd, _ in table):
            break
        cs = [w / (nd - k15) ** 1.5 for nd, w in table]
        lc = sum(math.log(x) for x in cs) / len(cs)
        e = sum((math.log(w) - lc - 1.5 * math.log(nd - k15)) ** 2 for nd, w in table)
        if best15 is None or e < best15[0]:
            best15 = (e, k15, math.exp(lc))
    e, k15, c15 = best15
    print(f"with n = 3/2: C = {c15:.2f} grains/s, k = {k15:.2f} (residual {e:.2e})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
