#!/usr/bin/env python3
"""Issue 9's performance figures in one run (bench/perf.sh calls this).

  1. marble against the hand-vectorized limit (bench/limit) at widths 4, 8,
     16: osl-run's shading time is whole-process time at 11 passes minus 1
     pass (as OSL's figure was measured), the two interleaved round by round,
     best round kept; the ratio target is <= 1.0.
  2. ns per point of every shipped shader and the conformance perf/ shaders
     at widths 1/4/8/16 (osl-bench), the speedup of 16 over 1 and its mean
     (target >= 6x).
  3. JIT: source to callable for marble, median of 20, stage by stage
     (osl-jit-bench, target <= 15 ms); then the persistent kernel cache: a
     second osl-run compiles nothing.
  4. Scale: 2 threads against 1 on a 2048x2048 grid (target >= 1.9x); peak
     memory of a 4096x4096 run against its output image plus 64 MB.
  5. Divergence: mean fraction of active lanes per executed masked block
     for the divergent shaders (osl-run --lane-stats).

Timings depend on the machine and on what else runs: read the ratios,
which are measured side by side in one run. Not a test.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.path.join(ROOT, "build", "bin")
OSL_RUN = os.path.join(BIN, "osl-run")
MARBLE = os.path.join(ROOT, "shaders", "marble.osl")
PERF_SHADERS = ["shaders/escape.osl", "shaders/marble.osl", "shaders/tiles.osl",
                "conformance/perf/marble.osl", "conformance/perf/wood.osl",
                "conformance/perf/brick.osl", "conformance/perf/voronoi.osl"]
DIVERGENT = ["shaders/escape.osl", "shaders/tiles.osl", "conformance/perf/voronoi.osl"]


def run(cmd, **kw):
    return subprocess.run(cmd, cwd=ROOT, check=True, capture_output=True, text=True, **kw)


def wall(cmd):
    start = time.perf_counter()
    run(cmd)
    return time.perf_counter() - start


def section(title):
    print("\n== " + title, flush=True)


def build_limit(out):
    """marble_vec at W = 4, 8, 16, rebuilt when the source is newer."""
    src = os.path.join(ROOT, "bench", "limit", "marble_vec.cpp")
    exes = {}
    for w in (4, 8, 16):
        exe = os.path.join(out, "marble_vec%d" % w)
        if not os.path.exists(exe) or os.path.getmtime(exe) < os.path.getmtime(src):
            run(["clang++-19", "-O3", "-march=native", "-mprefer-vector-width=512",
                 "-ffp-contract=off", "-DW=%d" % w, src, "-o", exe])
        exes[w] = exe
    return exes


def limit_ratio(out, rounds, passes):
    section("1. marble against the hand-vectorized limit (1024x1024, 1 thread, best of %d "
            "interleaved rounds)" % rounds)
    print("osl-mlir: whole-process time of %d passes minus that of 1 pass (each the best of "
          "the rounds), per point and pass; in-process: the shading time --stats reports for "
          "the %d passes" % (passes, passes))
    exes = build_limit(out)
    points = 1024 * 1024
    limit, one, many, inproc = ({w: float("inf") for w in exes} for _ in range(4))
    for _ in range(rounds):
        for w, exe in exes.items():
            m = re.search(r"ns/point ([0-9.]+)", run([exe]).stdout)
            limit[w] = min(limit[w], float(m.group(1)))
            base = [OSL_RUN, MARBLE, "-g", "1024", "1024", "-t", "1", "--width", str(w),
                    "-o", "Cout", "null"]
            one[w] = min(one[w], wall(base + ["--iters", "1"]))
            start = time.perf_counter()
            err = run(base + ["--iters", str(passes), "--stats"]).stderr
            many[w] = min(many[w], time.perf_counter() - start)
            ns = float(re.search(r"shading: ([0-9.]+) ns per point", err).group(1))
            inproc[w] = min(inproc[w], ns)
    print("%6s %10s %14s %8s %14s %8s" % ("width", "limit ns", "osl-mlir ns", "ratio",
                                           "in-process ns", "ratio"))
    for w in exes:
        ours = (many[w] - one[w]) / (passes - 1) / points * 1e9
        print("%6d %10.2f %14.2f %8.2f %14.2f %8.2f" % (
            w, limit[w], ours, ours / limit[w], inproc[w], inproc[w] / limit[w]))


def shader_table():
    section("2. ns per point, widths 1/4/8/16 (osl-bench: 512x512, 1 thread)")
    text = run([os.path.join(BIN, "osl-bench")] + PERF_SHADERS).stdout
    print(text.rstrip())
    speedups = [float(m.group(1)) for m in
                re.finditer(r"^\S+\s+16\s+[0-9.]+\s+([0-9.]+)x", text, re.M)]
    if speedups:
        print("mean speedup of width 16 over width 1: %.2fx over %d shaders (min %.2fx)"
              % (sum(speedups) / len(speedups), len(speedups), min(speedups)))


def stage_lines(stderr):
    """(stage, ms) pairs of osl-run --stats, compile stages only."""
    stages = []
    for m in re.finditer(r"^  (\S[^\n]*?)\s+([0-9.]+) ms$", stderr, re.M):
        if m.group(1) not in ("shading", "write images", "total"):
            stages.append((m.group(1), float(m.group(2))))
    return stages


def jit(out):
    section("3. JIT: OSL source to callable kernel, marble")
    print(run([os.path.join(BIN, "osl-jit-bench"), "--compiles", "20", MARBLE]).stdout.rstrip())
    cache = tempfile.mkdtemp(prefix="cache-", dir=out)
    try:
        for label in ("first run, empty cache", "second run"):
            err = run([OSL_RUN, MARBLE, "-g", "64", "64", "-o", "Cout", "null", "--stats",
                       "--cache-dir", cache]).stderr
            use = re.search(r"kernel cache: (.*)", err).group(1)
            stages = stage_lines(err)
            print("  %-24s %-30s source to kernel %7.2f ms (%s)" % (
                label, use, sum(ms for _, ms in stages),
                ", ".join("%s %.2f" % s for s in stages)))
    finally:
        shutil.rmtree(cache, ignore_errors=True)


def shading_ns(cmd):
    m = re.search(r"shading: ([0-9.]+) ns per point", run(cmd).stderr)
    return float(m.group(1))


def peak_rss_mb(cmd):
    """Peak resident memory of one child process, in MB."""
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode:
        sys.exit("failed: " + " ".join(cmd))
    return usage.ru_maxrss / 1024.0


def scale(out, rounds):
    section("4. threads and memory")
    base = [OSL_RUN, MARBLE, "-g", "2048", "2048", "--iters", "3", "-o", "Cout", "null",
            "--stats"]
    best = {1: float("inf"), 2: float("inf")}
    for _ in range(rounds):
        for t in (1, 2):
            best[t] = min(best[t], shading_ns(base + ["-t", str(t)]))
    print("  marble 2048x2048: 1 thread %.2f ns/point, 2 threads %.2f: %.2fx (target >= 1.9x)"
          % (best[1], best[2], best[1] / best[2]))
    image = os.path.join(out, "memory.exr")
    small = peak_rss_mb([OSL_RUN, MARBLE, "-g", "16", "16", "-o", "Cout", image])
    big = peak_rss_mb([OSL_RUN, MARBLE, "-g", "4096", "4096", "-o", "Cout", image])
    os.remove(image)
    image_mb = 4096 * 4096 * 3 * 4 / 2**20
    grown = big - small
    print("  marble 4096x4096 to EXR: peak RSS %.0f MB; a 16x16 run (code, libraries): %.0f MB;"
          % (big, small))
    print("  growth %.0f MB = output image %.0f MB + %.0f MB (target: <= image + 64 MB)"
          % (grown, image_mb, grown - image_mb))


def divergence():
    section("5. divergence: active lanes per executed masked block (512x512)")
    print("%-28s %6s %14s %10s" % ("shader", "width", "blocks", "active"))
    for shader in DIVERGENT:
        for w in (4, 8, 16):
            text = run([OSL_RUN, shader, "-g", "512", "512", "--width", str(w),
                        "--lane-stats", "--no-cache", "-o", "Cout", "null"]).stdout
            m = re.search(r"lane stats: (\d+) masked blocks executed, ([0-9.]+)%", text)
            print("%-28s %6d %14s %9s%%" % (shader, w, m.group(1), m.group(2)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (default 3)")
    ap.add_argument("--passes", type=int, default=31,
                    help="passes of the long osl-run in the limit comparison (default 31)")
    ap.add_argument("--only", type=int, choices=range(1, 6), help="run one section")
    a = ap.parse_args()
    for tool in ("osl-run", "osl-bench", "osl-jit-bench"):
        if not os.path.exists(os.path.join(BIN, tool)):
            sys.exit("build first (scripts/build.sh): %s is missing" % tool)
    out = os.path.join(ROOT, "build", "bench-perf")
    os.makedirs(out, exist_ok=True)
    cpu = re.search(r"^model name\s*:\s*(.*)$", open("/proc/cpuinfo").read(), re.M)
    print("osl-mlir performance, %s, %s, %d cores" % (
        time.strftime("%Y-%m-%d %H:%M"), cpu.group(1) if cpu else "unknown CPU",
        os.cpu_count()))
    sections = [lambda: limit_ratio(out, a.rounds, a.passes), shader_table, lambda: jit(out),
                lambda: scale(out, a.rounds), divergence]
    for i, run_section in enumerate(sections, 1):
        if a.only in (None, i):
            run_section()


if __name__ == "__main__":
    main()
