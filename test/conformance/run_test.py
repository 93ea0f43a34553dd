#!/usr/bin/env python3
"""Run one conformance test with osl-run at every width and judge it.

  run_test.py --osl-run PATH --corpus DIR --test NAME [--widths 1,4,8,16]

Each output is compared with OSL's reference image the way OSL's own test
suite does (idiff with the manifest's failthresh/failpercent/hardfail and
optional failrelative; see the corpus README), and the images of all
widths must be bit-identical to each other (idiff with zero thresholds).
Prints one PASS/FAIL line per width and exits non-zero on any failure.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


IMGDIFF = None  # osl-imgdiff beside osl-run


def idiff(args, cwd):
    # osl-imgdiff passes images within the failing threshold everywhere (as
    # idiff would) in milliseconds; idiff, 0.7 s a call, judges the rest.
    if IMGDIFF:
        opts = dict(zip(args[:-2:2], args[1:-2:2]))
        limit = min(float(opts.get("-fail", 0)), float(opts.get("-hardfail", "inf")))
        r = subprocess.run([IMGDIFF, "--fail", repr(limit)] + args[-2:], cwd=cwd,
                           capture_output=True, text=True)
        if r.returncode == 0:
            return 0, r.stdout.strip()
    r = subprocess.run(["idiff"] + args, cwd=cwd, capture_output=True, text=True)
    return r.returncode, " ".join((r.stdout + r.stderr).split()[-30:])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--osl-run", required=True)
    ap.add_argument("--corpus", required=True)
    ap.add_argument("--test", required=True)
    ap.add_argument("--widths", default="1,4,8,16")
    a = ap.parse_args()
    global IMGDIFF
    imgdiff = os.path.join(os.path.dirname(os.path.abspath(a.osl_run)), "osl-imgdiff")
    IMGDIFF = imgdiff if os.access(imgdiff, os.X_OK) else None
    corpus = os.path.abspath(a.corpus)
    tests = {t["name"]: t for t in json.load(open(os.path.join(corpus, "manifest.json")))}
    if a.test not in tests:
        print("no test named %s in the manifest" % a.test)
        return 2
    t = tests[a.test]
    tol = t["tolerance"]
    widths = [int(w) for w in a.widths.split(",")]
    out = tempfile.mkdtemp(prefix="osl-conformance-")
    failures = 0
    images = {}
    for w in widths:
        cmd = [a.osl_run, "--width", str(w), "-t", "1"] + t["args"]
        for o in t["outputs"]:
            path = os.path.join(out, "w%d.%s.exr" % (w, o["name"]))
            images[(w, o["name"])] = path
            cmd += ["-o", o["name"], path]
        cmd.append(t["shader"])
        r = subprocess.run(cmd, cwd=corpus, capture_output=True, text=True)
        msgs = []
        if r.returncode != 0:
            msgs.append("osl-run failed (%d): %s" % (r.returncode, (r.stdout + r.stderr)[-800:]))
        else:
            for o in t["outputs"]:
                args = ["-fail", str(tol["failthresh"]), "-failpercent", str(tol["failpercent"]),
                        "-hardfail", str(tol["hardfail"]), "-warn", str(2 * tol["failthresh"]),
                        "-warnpercent", str(tol["failpercent"])]
                if "failrelative" in tol:
                    args += ["-failrelative", str(tol["failrelative"])]
                code, text = idiff(args + [o["ref"], images[(w, o["name"])]], corpus)
                if code not in (0, 1):
                    msgs.append("%s differs from OSL's reference: %s" % (o["name"], text))
                if w != widths[0]:
                    code, text = idiff(["-fail", "0", "-failpercent", "0", "-hardfail", "0",
                                        images[(widths[0], o["name"])], images[(w, o["name"])]],
                                       corpus)
                    if code != 0:
                        msgs.append("%s at width %d is not bit-identical to width %d: %s"
                                    % (o["name"], w, widths[0], text))
        print("%s %s width %d%s" % ("PASS" if not msgs else "FAIL", a.test, w,
                                     "".join("\n    " + m for m in msgs)))
        failures += bool(msgs)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
