#!/usr/bin/env python3
"""A render is the same image, bit for bit, at widths 1, 4, 8 and 16 and
with 1 or 2 threads: the scenes with per-point closure weights
(noisy_diffuse), layered closures and glass.

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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--osl-run", required=True)
    args = ap.parse_args()
    osl_run = os.path.abspath(args.osl_run)
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in ("noisy_diffuse", "layered_sum", "glass"):
            images = {}
            for width, threads in ((1, 1), (4, 2), (8, 1), (16, 2)):
                out = os.path.join(tmp, "%s_%d.exr" % (scene, width))
                subprocess.run([osl_run, "--scene", "scenes/%s.xml" % scene, "-o", out,
                                "-r", "48", "32", "-aa", "3", "--width", str(width), "-t",
                                str(threads), "--seed", "7", "--no-cache"],
                               cwd=CORPUS, check=True)
                images[width] = pixels(out)
            same = all(images[w] == images[1] for w in (4, 8, 16))
            print("%s %s" % ("PASS" if same else "FAIL", scene))
            failed += not same
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
