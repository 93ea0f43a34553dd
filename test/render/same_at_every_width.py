#!/usr/bin/env python3
"""A render is the same image, bit for bit, at widths 1, 4, 8 and 16, with
1 or 2 threads and with the renderer's lane loops built for each
instruction set this CPU runs (OSL_MLIR_RENDER_ISA): the scenes with
per-point closure weights (noisy_diffuse), layered closures and glass.

  python3 same_at_every_width.py --osl-run build/bin/osl-run
"""
import argparse
import os
import subprocess
import sys
import tempfile

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "render")


def pixels(path):
    dump = subprocess.run(["oiiotool", "--dumpdata", path], check=True, capture_output=True,
                          text=True).stdout
    return dump.split("\n", 1)[1]  # the first line names the file


def cpu_isas():
    """The render ISAs this CPU runs (LaneKernels.cpp's choice, from /proc/cpuinfo)."""
    flags = set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    break
    except OSError:
        pass
    isas = {"generic"}
    if "avx2" in flags:
        isas.add("avx2")
    if {"avx512f", "avx512vl", "avx512bw", "avx512dq"} <= flags:
        isas.add("avx512")
    return isas


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--osl-run", required=True)
    args = ap.parse_args()
    osl_run = os.path.abspath(args.osl_run)
    failed = 0
    isas = cpu_isas()
    print("instruction sets: " + " ".join(sorted(isas)))
    with tempfile.TemporaryDirectory() as tmp:
        for scene in ("noisy_diffuse", "layered_sum", "glass"):
            images = {}
            runs = [(1, 1, "generic"), (4, 2, "avx2"), (8, 1, "avx512"), (16, 2, "generic"),
                    (16, 1, "avx2"), (1, 2, "avx512")]
            for width, threads, isa in runs:
                if isa not in isas:
                    continue
                out = os.path.join(tmp, "%s_%d_%s.exr" % (scene, width, isa))
                env = dict(os.environ, OSL_MLIR_RENDER_ISA=isa)
                subprocess.run([osl_run, "--scene", "scenes/%s.xml" % scene, "-o", out,
                                "-r", "48", "32", "-aa", "3", "--width", str(width), "-t",
                                str(threads), "--seed", "7", "--no-cache"],
                               cwd=CORPUS, check=True, env=env)
                images[(width, threads, isa)] = pixels(out)
            first = next(iter(images.values()))
            same = all(image == first for image in images.values())
            print("%s %s" % ("PASS" if same else "FAIL", scene))
            failed += not same
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
