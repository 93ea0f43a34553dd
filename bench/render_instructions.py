#!/usr/bin/env python3
"""Instructions a render executes per path at width 16 and width 1, counted
by valgrind's callgrind: a measure that does not move with the machine's
noise (this VM's render times swing by a third between runs), for A/B of
renderer changes.

  python3 bench/render_instructions.py [--scenes a,b] [--res 32] [--aa 4]
                                       [--baseline OTHER_OSL_RUN]

Each scene of render/ is rendered by osl-run --scene with one thread, and
only osl::render::PathWave::run (the paths, the shading kernels they call
and everything below; not the background's importance table, shaded once
before them) is counted. Valgrind runs no AVX-512, so the
renderer's lane loops are its AVX2 ones and the kernels are compiled for
what valgrind reports; the counts compare binaries and widths, not
machines. With --baseline, the same counts for another osl-run binary,
and each count's change. Needs valgrind (apt install valgrind).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "render")


def instructions(osl_run, scene, width, res, aa, tmp):
    """Instructions executed in PathWave::run, and the paths traced."""
    counts = os.path.join(tmp, "callgrind.out")
    cmd = ["valgrind", "--tool=callgrind", "--callgrind-out-file=" + counts,
           "--toggle-collect=osl::render::PathWave::run*", osl_run, "--scene", scene,
           "-o", os.path.join(tmp, "out.exr"), "-r", str(res), str(res), "-aa", str(aa),
           "--width", str(width), "-t", "1", "--stats"]
    run = subprocess.run(cmd, cwd=CORPUS, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (run.returncode, " ".join(cmd), run.stderr[-2000:]))
    paths = int(re.search(r"paths: (\d+)", run.stderr).group(1))
    with open(counts) as f:
        total = int(re.search(r"^totals: (\d+)", f.read(), re.M).group(1))
    return total, paths


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--osl-run", default=os.path.join(ROOT, "build", "bin", "osl-run"))
    ap.add_argument("--baseline", help="another osl-run binary to count beside it")
    ap.add_argument("--scenes", help="comma-separated scene names (default: every scene)")
    ap.add_argument("--res", type=int, default=32)
    ap.add_argument("--aa", type=int, default=4)
    args = ap.parse_args()
    if not shutil.which("valgrind"):
        sys.exit("valgrind not found: apt install valgrind")
    scenes = (args.scenes.split(",") if args.scenes else
              sorted(f[:-4] for f in os.listdir(os.path.join(CORPUS, "scenes"))
                     if f.endswith(".xml")))
    binaries = [("", args.osl_run)] + ([("baseline ", args.baseline)] if args.baseline else [])
    header = "| scene |"
    for label, _ in binaries:
        header += " %sw1 instr/path | %sw16 | %sw1/w16 |" % (label, label, label)
    if args.baseline:
        header += " w1 change | w16 change |"
    print(header)
    print("|---" * (header.count("|") - 1) + "|")
    ratios = {label: [] for label, _ in binaries}
    with tempfile.TemporaryDirectory() as tmp:
        for name in scenes:
            scene = os.path.join("scenes", name + ".xml")
            row, per = "| %s |" % name, {}
            for label, binary in binaries:
                for width in (1, 16):
                    total, paths = instructions(binary, scene, width, args.res, args.aa, tmp)
                    per[(label, width)] = total / paths
                ratio = per[(label, 1)] / per[(label, 16)]
                ratios[label].append(ratio)
                row += " %.0f | %.0f | %.2fx |" % (per[(label, 1)], per[(label, 16)], ratio)
            if args.baseline:
                for width in (1, 16):
                    row += " %+.1f%% |" % (100 * (per[("", width)] / per[("baseline ", width)] - 1))
            print(row, flush=True)
    for label, _ in binaries:
        print("\n%smean width 1 over width 16 in instructions: %.2fx"
              % (label, sum(ratios[label]) / len(ratios[label])))


if __name__ == "__main__":
    main()
