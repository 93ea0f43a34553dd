#!/usr/bin/env python3
"""Speed against accuracy of the math library and of the shipped shaders.

One command draws everything (from the repository root, after building):

    python3 bench/math_chart.py [--build build]

1. bench/osl-mathbench: for every library math function and implementation
   (--math=fast, default, precise; MLIR's polynomial approximations; glibc's
   libmvec) at widths 1, 4, 8, 16: max ULP and max absolute error against the
   function evaluated in double with glibc's libm, and ns per point.
2. Each shaders/*.osl at every --math level and widths 1 and 16: ns per point
   (osl-run --stats, one thread) and the mean and max error of its Cout image
   against the same shader evaluated in double (--math=double) (idiff).
3. Writes bench/math.csv, bench/shaders-math.csv, bench/math-chart.svg,
   bench/shader-math-chart.svg and bench/MATH.md (the tables).

Timings depend on the machine and its load: compare rows of one run.
Needs python3-matplotlib and idiff (openimageio-tools).
"""
import argparse
import csv
import io
import math
import os
import re
import subprocess
import sys
import tempfile

try:
    import matplotlib
except ImportError:
    # Debian's python3-matplotlib is on the system python; another python3
    # (pyenv, venv) first in PATH would not see it.
    if sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    raise

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BENCH = os.path.join(ROOT, "bench")
IMPLS = ["fast", "default", "precise", "polynomial", "libmvec"]
LEVELS = ["fast", "default", "precise"]
SHADER_LEVELS = LEVELS + ["double"]
COLORS = {"fast": "tab:red", "default": "tab:blue", "precise": "tab:green", "double": "black",
          "polynomial": "tab:orange", "libmvec": "tab:purple"}


def run_mathbench(build, sweep):
    out = subprocess.run([os.path.join(build, "bin", "osl-mathbench"), "--sweep", str(sweep)],
                         check=True, capture_output=True, text=True).stdout
    with open(os.path.join(BENCH, "math.csv"), "w") as f:
        f.write(out)
    return list(csv.DictReader(io.StringIO(out)))


def shade(osl_run, shader, level, width, grid, iters, image, repeats=3):
    """Best ns per point of `repeats` runs (the machine may be shared)."""
    return min(shade_once(osl_run, shader, level, width, grid, iters, image)
               for _ in range(repeats))


def shade_once(osl_run, shader, level, width, grid, iters, image):
    cmd = [osl_run, shader, "-g", str(grid), str(grid), "--math=" + level, "--width",
           str(width), "-t", "1", "--iters", str(iters), "--stats", "-o", "Cout", image]
    res = subprocess.run(cmd, check=True, capture_output=True, text=True)
    m = re.search(r"shading: ([0-9.]+) ns per point", res.stdout + res.stderr)
    if not m:
        sys.exit("no 'ns per point' in the output of " + " ".join(cmd))
    return float(m.group(1))


def image_error(a, b):
    res = subprocess.run(["idiff", "-v", "-a", "-fail", "1e30", "-warn", "1e30", a, b],
                         capture_output=True, text=True)
    mean = re.search(r"Mean error = ([0-9.e+-]+|inf|nan)", res.stdout)
    peak = re.search(r"Max error\s+= ([0-9.e+-]+|inf|nan)", res.stdout)
    if not mean or not peak:
        sys.exit("idiff failed on %s %s:\n%s%s" % (a, b, res.stdout, res.stderr))
    return float(mean.group(1)), float(peak.group(1))


def run_shaders(build, grid, iters):
    osl_run = os.path.join(build, "bin", "osl-run")
    shaders = sorted(f for f in os.listdir(os.path.join(ROOT, "shaders")) if f.endswith(".osl"))
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in shaders:
            path = os.path.join(ROOT, "shaders", name)
            images = {}
            for level in SHADER_LEVELS:
                for width in (1, 16):
                    image = os.path.join(tmp, "%s-%s-%d.exr" % (name, level, width))
                    ns = shade(osl_run, path, level, width, grid, iters, image)
                    images[(level, width)] = image
                    rows.append({"shader": name[:-4], "level": level, "width": width,
                                 "ns_per_point": ns})
            for row in rows:
                if row["shader"] != name[:-4]:
                    continue
                img = images[(row["level"], row["width"])]
                row["mean_error"], row["max_error"] = image_error(img, images[("double", 16)])
                # Same level, other width: must be bit-identical.
                other = images[(row["level"], 17 - row["width"])]
                row["width_identical"] = image_error(img, other)[1] == 0
    with open(os.path.join(BENCH, "shaders-math.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    return rows


def fnum(v, digits=3):
    v = float(v)
    if math.isinf(v):
        return "inf"
    if v == 0:
        return "0"
    return "%.*g" % (digits, v)


def draw_functions(rows):
    functions = list(dict.fromkeys(r["function"] for r in rows))
    cols = 5
    nrows = (len(functions) + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 3.2 * nrows))
    for ax, fn in zip(axes.flat, functions):
        # fast last and smaller: it coincides with default or polynomial.
        for impl in ["polynomial", "default", "precise", "libmvec", "fast"]:
            pts = [r for r in rows if r["function"] == fn and r["impl"] == impl]
            if not pts:
                continue
            xs = [float(r["ns_per_point"]) for r in pts]
            # Max ULP; 0 drawn at 0.1, inf at 1e12 (both marked in the table).
            ys = [min(max(float(r["max_ulp"]), 0.1), 1e12) for r in pts]
            ax.plot(xs, ys, "-", color=COLORS[impl], alpha=0.4)
            for r, x, y in zip(pts, xs, ys):
                ax.plot(x, y, "o" if r["width"] == "16" else "s", color=COLORS[impl],
                        markersize=(6 if r["width"] in ("1", "16") else 3) *
                        (0.6 if impl == "fast" else 1),
                        fillstyle="full" if r["width"] == "16" else "none")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(fn)
        ax.set_xlabel("ns per point")
        ax.set_ylabel("max error (ULP)")
        ax.grid(True, which="major", alpha=0.3)
    for ax in list(axes.flat)[len(functions):]:
        ax.axis("off")
    handles = [plt.Line2D([], [], color=COLORS[i], marker="o", linestyle="-", label=i)
               for i in IMPLS]
    handles.append(plt.Line2D([], [], color="gray", marker="o", linestyle="", label="width 16"))
    handles.append(plt.Line2D([], [], color="gray", marker="s", fillstyle="none", linestyle="",
                              label="width 1"))
    fig.legend(handles=handles, loc="lower right", ncol=2, fontsize=11)
    fig.suptitle("OSL library math: max error against a double-precision evaluation vs "
                 "single-thread ns per point (line: widths 1, 4, 8, 16)")
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(os.path.join(BENCH, "math-chart.svg"))
    plt.close(fig)


def draw_shaders(rows):
    shaders = list(dict.fromkeys(r["shader"] for r in rows))
    fig, axes = plt.subplots(1, len(shaders), figsize=(5 * len(shaders), 4))
    for ax, name in zip(axes, shaders):
        for level in SHADER_LEVELS:
            pts = [r for r in rows if r["shader"] == name and r["level"] == level]
            xs = [float(r["ns_per_point"]) for r in pts]
            ys = [max(float(r["max_error"]), 1e-10) for r in pts]
            ax.plot(xs, ys, "o-", color=COLORS[level], label=level)
            for r, x, y in zip(pts, xs, ys):
                ax.annotate("w%s" % r["width"], (x, y), fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(name)
        ax.set_xlabel("ns per point (1 thread)")
        ax.set_ylabel("max |error| vs double evaluation (0 at 1e-10)")
        ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(BENCH, "shader-math-chart.svg"))
    plt.close(fig)


HEADER = """# Math library: error against speed

Generated by `python3 bench/math_chart.py` (do not edit; rerun it). Single
thread, timings of one run on one machine: compare rows, not machines.

**Implementations.** `fast`, `default` and `precise` are `--math=` levels
(osl-approximate-math): `default` is OSL's own algorithms (OIIO fast_*; the
conformance corpus depends on it); `fast` takes per op the faster of OSL's
algorithm and MLIR's polynomial approximation (OSL's for tan, atan, atan2,
pow; MLIR's otherwise); `precise` evaluates each transcendental op in double
with glibc's libm, one call per lane, and rounds once to float. `polynomial`
is MLIR's approximations for every op and `libmvec` glibc's vector functions
(`_ZGV{b,d,e}N*`, scalar libm at width 1): measured only, not levels
(libmvec's results differ between widths). Every level is bit-identical
across widths (tested). Each row is the OSL library function as a shader
computes it (LaneMath.h, OSL's edge rules included), so asin, acos, sinh,
cosh, erfc, cbrt and inversesqrt are compositions of several ops. perlin,
simplex and cellnoise (2D) contain no math op, so every level runs the same
code (one row); their reference is the same kernel evaluated in double by
osl-evaluate-in-double, so the error is that of their float arithmetic.

**Error.** Against the same function evaluated in double with glibc's libm
(OslCompiler/MathKernel.h), on a stratified sweep of the domain (half
uniform, half log-uniform magnitudes; pairs for atan2 and pow). Points whose
reference lies outside the normal float range up to 2^126 (where OSL's exp
saturates) are left out of the maxima. `max ULP` is in ULPs of the exact
value; `CR steps` is the distance in floats from the correctly rounded
result (what `precise` promises: at most 1). Near zeros of sin, cos, tan,
asin, atan the relative error of the approximations is large; their bound is
absolute. `NaN edges`: edge inputs (0, -0, denormals, +-FLT_MAX, +-Inf,
negative bases; not NaN) where the implementation gives NaN and OSL's
`default` gives a number. `bound` is the documented bound the stability
tests (unittests/Math) hold each implementation to.

**Where approximations break down** (the documented results, tested):
log/log2/log10 of x <= 0 is the log of FLT_MIN (-87.34 for log) at every
level; sqrt and inversesqrt of x < 0 are 0; pow of a negative base is 0
unless the exponent is an integer, pow(x, 0) = 1, pow(0, y) = 0; atan2(0, 0)
= 0; sin and cos stay in [-1, 1] at any argument (a result a failed
reduction pushes outside is 0, OSL's rule, also applied to MLIR's); exp
saturates at 2^+-126 at `default` (OSL) and overflows to +inf / underflows
to 0 at `fast` and `precise` (IEEE); MLIR's tan (sin/cos, `polynomial`
only) gives +-inf or NaN at |x| >~ 1e5 and has no bound; `fast` sinh/cosh
give +-inf for |x| > 87.3, where exp(-|x|) underflows.
"""


def function_table(rows):
    out = ["## Functions", "", "![error against ns per point](math-chart.svg)", "",
           "| function | impl | max ULP | max abs | CR steps | ns/pt w1 | w4 | w8 | w16 "
           "| NaN edges | bound |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    functions = list(dict.fromkeys(r["function"] for r in rows))
    for fn in functions:
        for impl in IMPLS:
            pts = {r["width"]: r for r in rows if r["function"] == fn and r["impl"] == impl}
            if not pts:
                continue
            r16 = pts["16"]
            # Error of the levels is the same at every width; libmvec's is
            # the worst width's.
            worst = max(pts.values(), key=lambda r: float(r["max_ulp"]))
            bound = ""
            if r16["bound_ulp"] or r16["bound_abs"]:
                bu, ba = float(r16["bound_ulp"]), float(r16["bound_abs"])
                if math.isinf(bu):
                    bound = "none"
                elif ba > 0:
                    bound = "abs " + fnum(ba, 2)
                else:
                    bound = ("%s CR steps" if impl == "precise" else "%s ULP") % fnum(bu, 2)
            out.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                fn, impl, fnum(worst["max_ulp"]), fnum(worst["max_abs"]),
                worst["cr_steps"], fnum(pts["1"]["ns_per_point"]),
                fnum(pts["4"]["ns_per_point"]), fnum(pts["8"]["ns_per_point"]),
                fnum(r16["ns_per_point"]), max(int(r["nan_edges"]) for r in pts.values()),
                bound))
    return out


SHADER_TEXT = """## Shaders

![shader error against ns per point](shader-math-chart.svg)

Each shaders/*.osl on a %dx%d grid, one thread, per --math level and width:
ns per point and the mean and max absolute error of its `Cout` image against
the same shader evaluated in double precision (`--math=double`, width 16:
osl-evaluate-in-double turns every float value of the kernel into f64 after
precise math; inputs are extended exactly and the output rounded once). So
the error includes the shader's own float arithmetic and noise, not only the
math functions: marble calls no transcendental function (noise and abs), so
its error is the same at every level; escape (sqrt only, exact everywhere)
iterates a chaotic map whose float and double orbits part near the set's
boundary, where a point's iteration count, hence its colour band, changes;
tiles calls sin in loops of per-tile length. `same at w1/w16`: the image is
bit-identical at widths 1 and 16.
"""


def shader_table(rows, grid):
    out = [SHADER_TEXT % (grid, grid),
           "| shader | level | width | ns/pt | mean error | max error | same at w1/w16 |",
           "|---|---|---|---|---|---|---|"]
    for r in rows:
        out.append("| %s | %s | %s | %s | %s | %s | %s |" % (
            r["shader"], r["level"], r["width"], fnum(r["ns_per_point"]),
            fnum(r["mean_error"]), fnum(r["max_error"]), "yes" if r["width_identical"] else "NO"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--sweep", type=int, default=1 << 17)
    ap.add_argument("--grid", type=int, default=256)
    ap.add_argument("--iters", type=int, default=5)
    args = ap.parse_args()
    rows = run_mathbench(args.build, args.sweep)
    draw_functions(rows)
    shader_rows = run_shaders(args.build, args.grid, args.iters)
    draw_shaders(shader_rows)
    with open(os.path.join(BENCH, "MATH.md"), "w") as f:
        f.write(HEADER + "\n" + "\n".join(function_table(rows)) + "\n\n" +
                "\n".join(shader_table(shader_rows, args.grid)) + "\n")
    print("wrote bench/math.csv, bench/shaders-math.csv, bench/math-chart.svg, "
          "bench/shader-math-chart.svg, bench/MATH.md")


if __name__ == "__main__":
    main()
