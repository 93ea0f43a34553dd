#!/usr/bin/env python3
"""Render throughput per scene: samples (paths) per second at width 16
against width 1 on the same scene, in one run, and the mean fraction of
active lanes in the shading batches.

  python3 bench/render_bench.py [--aa 8] [--rounds 3] [--threads 1]

Each scene of render/ is rendered at 128x128 with aa x aa paths per pixel
by osl-run --scene at widths 1 and 16, interleaved, best of --rounds. The
time is osl-run's own "rendering" stage (shaders compiled already), from
runs that do not time their kernels; the kernels' ns per point come from
one more run per width with --time-kernels (its clock reads per batch
would slow width 1's render by a third).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "render")


def render(osl_run, scene, width, aa, threads, out, time_kernels=False):
    """(samples per second, % of lanes active, kernel ns per point or None)"""
    cmd = [osl_run, "--scene", scene, "-o", out, "-r", "128", "128", "-aa", str(aa),
           "--width", str(width), "-t", str(threads), "--stats"]
    if time_kernels:
        cmd.append("--time-kernels")
    err = subprocess.run(cmd, cwd=CORPUS, check=True, capture_output=True, text=True).stderr
    ms = float(re.search(r"rendering\s+([\d.]+) ms", err).group(1))
    paths = int(re.search(r"paths: (\d+)", err).group(1))
    lanes = float(re.search(r"([\d.]+)% of lanes active", err).group(1))
    kernel = re.search(r"\(([\d.]+) ns per shaded point\)", err)
    return paths / (ms / 1000), lanes, float(kernel.group(1)) if kernel else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--osl-run", default=os.path.join(ROOT, "build", "bin", "osl-run"))
    ap.add_argument("--aa", type=int, default=8)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    scenes = sorted(f[:-4] for f in os.listdir(os.path.join(CORPUS, "scenes"))
                    if f.endswith(".xml"))
    print("| scene | samples/s width 1 | samples/s width 16 | speedup | active lanes (w16) "
          "| kernel ns/point w1 | w16 | kernel speedup |")
    print("|---|---|---|---|---|---|---|---|")
    speedups, kernel_speedups = [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.exr")
        for name in scenes:
            scene = os.path.join("scenes", name + ".xml")
            best = {1: 0.0, 16: 0.0}
            kernel = {1: float("inf"), 16: float("inf")}
            lanes = 0.0
            for _ in range(args.rounds):
                for width in (1, 16):
                    rate, active, _ = render(args.osl_run, scene, width, args.aa, args.threads,
                                             out)
                    best[width] = max(best[width], rate)
                    if width == 16:
                        lanes = active
            for width in (1, 16):
                kernel[width] = render(args.osl_run, scene, width, args.aa, args.threads, out,
                                       time_kernels=True)[2]
            speedups.append(best[16] / best[1])
            kernel_speedups.append(kernel[1] / kernel[16])
            print("| %s | %.0f | %.0f | %.2fx | %.1f%% | %.1f | %.1f | %.2fx |"
                  % (name, best[1], best[16], best[16] / best[1], lanes, kernel[1], kernel[16],
                     kernel[1] / kernel[16]))
            sys.stdout.flush()
    print("\nmean speedup of width 16 over width 1: %.2fx whole render, %.2fx in the shading "
          "kernels" % (sum(speedups) / len(speedups), sum(kernel_speedups) / len(kernel_speedups)))


if __name__ == "__main__":
    main()
