#!/usr/bin/env python3
"""White furnace per closure: a sphere whose Ci is one white closure, inside
a uniform white background, rendered by osl-run --scene. A closure that
scatters all light it receives keeps every pixel at 1; one that loses
energy by design (Oren-Nayar, single-scattering microfacets, Phong, Ward,
sheen, conductors) stays below 1 and above a floor; none may exceed its
bound. Exit status 0 when every closure holds.

  python3 furnace.py --osl-run build/bin/osl-run --width 16
"""
import argparse
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "render", "tools"))
import imgcmp  # noqa: E402

ETA = "backfacing() ? 1.0 / 1.5 : 1.5"
# name, Ci expression, (lowest, highest) allowed image mean
CLOSURES = [
    ("diffuse", "diffuse(N)", (0.999, 1.001)),
    ("translucent", "translucent(N)", (0.995, 1.001)),
    ("reflection", "reflection(N)", (0.999, 1.001)),
    ("glass", "reflection(N, %s) + refraction(N, %s)" % (ETA, ETA), (0.995, 1.001)),
    ("transparent", "transparent()", (0.999, 1.001)),
    ("mixture", "0.5 * diffuse(N) + 0.5 * reflection(N)", (0.999, 1.001)),
    ("microfacet_glass", 'microfacet("ggx", N, 0.01, %s, 2)' % ETA, (0.98, 1.001)),
    ("dielectric_bsdf",
     'dielectric_bsdf(N, vector(0), color(1), color(1), 0.01, 0.01, 1.5, "ggx")', (0.98, 1.001)),
    ("translucent_bsdf", "translucent_bsdf(N, color(1))", (0.995, 1.001)),
    ("transparent_bsdf", "transparent_bsdf()", (0.999, 1.001)),
    ("subsurface_bssrdf", "subsurface_bssrdf(N, color(1), 1.0, color(1), 0)", (0.999, 1.001)),
    ("uniform_edf", "uniform_edf(color(1))", (0.999, 1.001)),
    ("oren_nayar", "oren_nayar(N, 0.5)", (0.8, 1.0)),
    ("oren_nayar_diffuse_bsdf", "oren_nayar_diffuse_bsdf(N, color(1), 0.5)", (0.8, 1.0)),
    ("oren_nayar_energy",
     'oren_nayar_diffuse_bsdf(N, color(1), 0.8, "energy_compensation", 1)', (0.98, 1.02)),
    ("burley_diffuse_bsdf", "burley_diffuse_bsdf(N, color(1), 0.5)", (0.9, 1.1)),
    ("microfacet_ggx", 'microfacet("ggx", N, 0.3, 0, 0)', (0.8, 1.0)),
    ("microfacet_beckmann", 'microfacet("beckmann", N, 0.3, 0, 0)', (0.85, 1.0)),
    ("phong", "phong(N, 20)", (0.5, 1.0)),
    ("ward", "ward(N, dPdu, 0.2, 0.3)", (0.5, 1.0)),
    ("conductor_bsdf",
     'conductor_bsdf(N, vector(0), 0.2, 0.2, color(0.2, 0.9, 1.1), color(3.9, 2.4, 2.2), "ggx")',
     (0.5, 1.0)),
    ("generalized_schlick_bsdf",
     'generalized_schlick_bsdf(N, vector(0), color(1), color(0), 0.2, 0.2, color(1), color(1),'
     ' 5, "ggx")', (0.85, 1.0)),
    ("sheen_bsdf", "sheen_bsdf(N, color(1), 0.4)", (0.01, 1.0)),
]

# resolution="0": paths find the background by the BSDF's own sampling
# alone, so the mean measures the lobe (testrender's importance table would
# add its MIS noise to bounds this tight).
SCENE = """<World>
  <Camera eye="0, 0, 4" look_at="0, 0, 0" fov="40" />
  <ShaderGroup>shader white_background env;</ShaderGroup>
  <Background resolution="0" />
  <ShaderGroup>shader furnace_%s ball;</ShaderGroup>
  <Sphere center="0, 0, 0" radius="1" />
</World>
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--osl-run", required=True)
    ap.add_argument("--width", default="16")
    ap.add_argument("--only")
    args = ap.parse_args()
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(tmp, "white_background.osl"), "w") as f:
            f.write("shader white_background() { Ci = background(); }\n")
        for name, expr, (lo, hi) in CLOSURES:
            if args.only and name != args.only:
                continue
            with open(os.path.join(tmp, "furnace_%s.osl" % name), "w") as f:
                f.write("surface furnace_%s() { Ci = %s; }\n" % (name, expr))
            scene = os.path.join(tmp, "%s.xml" % name)
            with open(scene, "w") as f:
                f.write(SCENE % name)
            out = os.path.join(tmp, "%s.exr" % name)
            cmd = [args.osl_run, "--scene", scene, "-o", out, "--path", tmp, "-r", "32", "32",
                   "-aa", "8", "--width", args.width, "--no-cache"]
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                print("FAIL %-26s osl-run exited %d: %s" % (name, run.returncode, run.stderr))
                failed += 1
                continue
            w, h, pixels = imgcmp.read_rgb(out)
            values = [v for px in pixels for v in px]
            mean = sum(values) / len(values)
            ok = lo <= mean <= hi
            print("%s %-26s mean %.5f (allowed %.3f..%.3f)" % ("PASS" if ok else "FAIL", name,
                                                                mean, lo, hi))
            failed += not ok
    print("%d closures, %d failed" % (len([c for c in CLOSURES
                                           if not args.only or c[0] == args.only]), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
