#!/usr/bin/env python3
"""Issue 8's figures in one run: a 20-layer shader group
(bench/shaders/group/group20.grp) compiled unspecialised (-O0: parameters
are loads, every layer runs), with constant parameters (-O1) and fully
specialised (-O2: folding across layers, lazy layers, unread layers and
outputs gone). For each level: operations and layers before and after
specialisation, JIT time (front end to callable, best of N runs) and ns per
shading point (one thread, best of N), then -O2's speedups over the others.
The three levels are interleaved round by round so that machine load hits
them alike. Timings depend on the machine: read the ratios. Not a test.

  bench/group_bench.py [--rounds N] [--grid X] [--width W]
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OSL_RUN = os.path.join(ROOT, "build", "bin", "osl-run")
GROUP = os.path.join(ROOT, "bench", "shaders", "group", "group20.grp")
LEVELS = ["-O0", "-O1", "-O2"]
# Stages of osl-run --stats that make up the JIT time (source to callable).
COMPILE_STAGES = ["front end", "mlir passes", "llvm translate", "jit setup", "llvm opt",
                  "jit add", "jit codegen", "jit link", "library store"]


def run(level, grid, width):
    cmd = [OSL_RUN, "--no-cache", "-t", "1", "-g", str(grid), str(grid), level,
           "--group", GROUP, "-o", "Cout", "null", "--stats"]
    if width:
        cmd += ["--width", str(width)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stderr
    ms = {name: float(v) for name, v in re.findall(r"^\s+(.+?)\s+([0-9.]+) ms$", out, re.M)}
    group = re.search(r"group: before specialisation (\d+) layers, (\d+) ops; "
                      r"after (\d+) layers, (\d+) ops", out)
    ns = float(re.search(r"shading: ([0-9.]+) ns per point", out).group(1))
    width = re.search(r"width (\d+)", out).group(1)
    return {"jit": sum(ms.get(s, 0.0) for s in COMPILE_STAGES), "ns": ns,
            "counts": tuple(int(x) for x in group.groups()), "width": width}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--grid", type=int, default=512)
    ap.add_argument("--width", type=int, default=0, help="lanes (default: widest)")
    args = ap.parse_args()
    best = {}
    for _ in range(args.rounds):
        for level in LEVELS:
            r = run(level, args.grid, args.width)
            b = best.setdefault(level, r)
            b["jit"] = min(b["jit"], r["jit"])
            b["ns"] = min(b["ns"], r["ns"])
    print(f"20-layer group, {args.grid}x{args.grid} points, width {best['-O2']['width']}, "
          f"1 thread, best of {args.rounds}")
    print(f"{'level':6} {'layers':>13} {'ops':>13} {'JIT ms':>8} {'ns/point':>9}")
    for level in LEVELS:
        lb, ob, la, oa = best[level]["counts"]
        print(f"{level:6} {lb:>5} -> {la:<5} {ob:>5} -> {oa:<5} {best[level]['jit']:8.1f} "
              f"{best[level]['ns']:9.2f}")
    o2 = best["-O2"]
    lb, ob, la, oa = o2["counts"]
    print(f"-O2 removes {100 * (ob - oa) / ob:.0f}% of ops and {100 * (lb - la) / lb:.0f}% of layers")
    for level in ["-O0", "-O1"]:
        print(f"-O2 against {level}: JIT {best[level]['jit'] / o2['jit']:.2f}x faster, "
              f"shading {best[level]['ns'] / o2['ns']:.2f}x faster")


if __name__ == "__main__":
    sys.exit(main())
