#!/usr/bin/env python3
"""Two osl-run builds side by side on vs_osl.py's shaders (a change's effect).

  bench/ab_osl_run.py BEFORE AFTER [--width W] [--res N] [--passes P]
                      [--rounds R] [--only REGEX] [--skip REGEX]

Runs each shader that vs_osl.py times (shaders/, conformance/perf/,
bench/shaders/ and the OSL testsuite's image-writing folders) with both
binaries, interleaved, and prints each one's shading time per point -
osl-run --stats' own "shading" timer at N passes minus 1 pass (N at least
P, so that the passes take about 0.6 s), the median of R rounds - their ratio (AFTER / BEFORE), the geometric mean and the shaders
that moved by more than 5%. Copy the BEFORE binary aside before building the
change: each binary keys its own kernel cache. Not a test.
"""
import argparse
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import vs_osl  # noqa: E402


def shading_seconds(binary, case, width, res, passes):
    cmd = ([binary, "--width", str(width), "-t", "1", "-g", str(res), str(res),
            "--iters", str(passes), "-I", case.folder, "--stats"] +
           list(case.args) + [case.src])
    # Images go nowhere: only the timer matters here.
    for i in range(len(cmd) - 2):
        if cmd[i] == "-o":
            cmd[i + 2] = "null"
    p = subprocess.run(cmd, cwd=case.cwd, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        return float("nan")
    return vs_osl.our_shading_ms(p.stderr) / 1e3


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--width", type=int, default=vs_osl.host_width())
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--passes", type=int, default=6)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--only", default="")
    ap.add_argument("--skip", default="")
    ap.add_argument("--suite", default=vs_osl.SUITE)
    a = ap.parse_args()
    cases = vs_osl.project_cases()
    if os.path.isdir(a.suite):
        cases += vs_osl.suite_cases(a.suite)
    cases = [c for c in cases if re.search(a.only, c.name) and
             not (a.skip and re.search(a.skip, c.name))]
    points = a.res * a.res
    ratios = []
    print("%-40s %10s %10s %7s" % ("shader", "before ns", "after ns", "ratio"), flush=True)
    for c in cases:
        # Enough passes that they take about 0.6 s beyond the first (which
        # loads textures and pages in the images).
        one = shading_seconds(a.before, c, a.width, a.res, 1)
        many = shading_seconds(a.before, c, a.width, a.res, a.passes)
        per_pass = (many - one) / (a.passes - 1)
        passes = int(min(max(a.passes, 0.6 / max(per_pass, 1e-4) + 1), 400)) \
            if math.isfinite(per_pass) else a.passes
        runs = {"before": [], "after": []}
        for _ in range(a.rounds):
            for name, binary in (("before", a.before), ("after", a.after)):
                one = shading_seconds(binary, c, a.width, a.res, 1)
                many = shading_seconds(binary, c, a.width, a.res, passes)
                ns = (many - one) / (passes - 1) / points * 1e9
                if math.isfinite(ns):
                    runs[name].append(ns)
        # The median round: a first pass that happened to be slow (a texture
        # read, page faults) makes one round's difference small, and the
        # best of the rounds would keep exactly that one.
        best = {name: sorted(ns)[len(ns) // 2] for name, ns in runs.items() if ns}
        if len(best) < 2:
            print("%-40s %s" % (c.name, "fails with one of the builds: left out"), flush=True)
            continue
        ratio = best["after"] / best["before"] if best["before"] > 0 else float("nan")
        if math.isfinite(ratio) and ratio > 0:
            ratios.append((ratio, c.name))
        print("%-40s %10.2f %10.2f %7.2f" % (c.name, best["before"], best["after"], ratio),
              flush=True)
    if ratios:
        print("\ngeometric mean %.3f over %d shaders" % (
            vs_osl.geomean([r for r, _ in ratios]), len(ratios)))
        for r, name in sorted(ratios):
            if abs(r - 1) > 0.05:
                print("  %s %.2f" % (name, r))


if __name__ == "__main__":
    main()
