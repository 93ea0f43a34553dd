#!/usr/bin/env python3
"""Generated programs run by OSL itself and by osl-run, compared.

  bench/difftest_osl.py --osl PREFIX [--osl-run build/bin/osl-run]
                        [--seed 1] [--count 2000] [--jobs 2] [--keep DIR]

osl-difftest compares the SIMD kernels with osl-mlir's own one-point
reference, which shares the front end and most passes with them, so a
semantic bug common to both goes unseen. This runs the same generated
shaders (test/difftest/generate.py) through OSL 1.13.12 (oslc, then
testshade, scalar unless --batched; PREFIX is where
../shared/tools/build-osl-reference.sh installed it) and through osl-run
at the host's widest width,
on the same 16x16 grid (parameter defaults that exit() are left out: OSL
runs a default at the first use its optimizer leaves, so where such an exit
stops the shader is up to the optimizer), and compares every output image with OSL's
testsuite tolerances (idiff -fail 0.004 -failpercent 0.02 -hardfail 0.01
-failrelative 0.001).
Prints each mismatch with its cause class and a summary by class; the
programs that differ are kept in --keep (default build/difftest-osl).
"""
import argparse
import collections
import os
import re
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "test", "difftest"))
import generate  # noqa: E402

OUTPUTS = ["fa", "fb", "facc"]
GRID = ["-g", "16", "16"]
TOLERANCE = ["-fail", "0.004", "-failpercent", "0.02", "-hardfail", "0.01", "-failrelative", "0.001",
             "-warn", "0.008", "-warnpercent", "0.02"]


def widest_width():
    # osl-run's widest that the CPU runs natively.
    flags = open("/proc/cpuinfo").read()
    return 16 if " avx512f" in flags else 8


def run(cmd, cwd, timeout=120):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
        return p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        return -1, "timed out after %d s" % timeout


def first_line(text):
    for line in text.splitlines():
        if line.strip():
            return line.strip()[:160]
    return ""


def compare(seed, a, work):
    """('match'|cause, detail) for one generated program."""
    d = os.path.join(work, "gen_%d" % seed)
    os.makedirs(d, exist_ok=True)
    name = "gen_%d" % seed
    with open(os.path.join(d, name + ".osl"), "w") as f:
        f.write(generate.generate(seed, param_exit=False))
    env_bin = os.path.join(a.osl, "bin")
    rc, out = run([os.path.join(env_bin, "oslc"), "-q", name + ".osl"], d)
    if rc != 0:
        return "oslc rejects", first_line(out)
    osl_outs, mlir_outs = [], []
    for o in OUTPUTS:
        osl_outs += ["-o", o, "osl_%s.exr" % o]
        mlir_outs += ["-o", o, "mlir_%s.exr" % o]
    rc, out = run([os.path.join(env_bin, "testshade")] + (["--batched"] if a.batched else []) +
                  GRID + [name] + osl_outs, d)
    if rc != 0:
        return "testshade fails", first_line(out)
    rc, out = run([a.osl_run, "--width", str(a.width)] + GRID + [name + ".osl"] + mlir_outs, d)
    if rc != 0:
        return "osl-run fails", first_line(out)
    for o in OUTPUTS:
        rc, out = run(["idiff"] + TOLERANCE + ["osl_%s.exr" % o, "mlir_%s.exr" % o], d)
        if rc not in (0, 1):  # 0 match, 1 warning; 2 failure
            m = re.search(r"Max error\s*=\s*([^\s]+)", out)
            nan = "NaN" in out or "nan" in out
            cause = "differs: NaN/Inf" if nan else "differs"
            return "%s (%s)" % (cause, o), "max error %s" % (m.group(1) if m else "?")
    return "match", ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--osl", default=os.path.expanduser("~/.cache/osl-reference"))
    ap.add_argument("--osl-run", default=os.path.join(HERE, "..", "build", "bin", "osl-run"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=2000)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--width", type=int, default=widest_width(), help="osl-run's width")
    ap.add_argument("--batched", action="store_true",
                    help="OSL's batched backend (default: its scalar one, the reference)")
    ap.add_argument("--keep", default=os.path.join(HERE, "..", "build", "difftest-osl"))
    a = ap.parse_args()
    a.osl_run = os.path.abspath(a.osl_run)
    if not os.path.exists(os.path.join(a.osl, "bin", "testshade")):
        sys.exit("no testshade in %s/bin: run ../shared/tools/build-osl-reference.sh" % a.osl)
    os.environ["LD_LIBRARY_PATH"] = os.path.join(a.osl, "lib") + ":" + os.environ.get(
        "LD_LIBRARY_PATH", "")
    work = os.path.abspath(a.keep)
    os.makedirs(work, exist_ok=True)
    seeds = range(a.seed, a.seed + a.count)
    counts = collections.Counter()
    with ThreadPoolExecutor(a.jobs) as pool:
        for seed, (cause, detail) in zip(seeds, pool.map(lambda s: compare(s, a, work), seeds)):
            counts[cause.split(" (")[0]] += 1
            if cause == "match":
                shutil.rmtree(os.path.join(work, "gen_%d" % seed), ignore_errors=True)
            else:
                print("seed %d: %s: %s" % (seed, cause, detail), flush=True)
    print("seeds %d..%d at width %d: %s" % (
        a.seed, a.seed + a.count - 1, a.width,
        ", ".join("%s %d" % kv for kv in counts.most_common())))
    return 0 if counts["match"] == a.count else 1


if __name__ == "__main__":
    sys.exit(main())
