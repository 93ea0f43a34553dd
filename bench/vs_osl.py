#!/usr/bin/env python3
"""osl-run beside OSL's own batched backend, shader by shader (issue 17).

  bench/vs_osl.py [--osl PREFIX] [--width W] [--res N] [--rounds R]
                  [--only REGEX] [--skip REGEX] [--no-testsuite]

Runs OSL 1.13.12's testshade (built outside the project by
../shared/tools/build-osl-reference.sh into PREFIX, default
~/.cache/osl-reference) with --batched at width W (the host's widest: 16
with AVX-512, else 8) and osl-run --width W on the same shaders, grid,
parameters and outputs, one thread each:

  shaders/*.osl, conformance/perf/*.osl, bench/shaders/*.osl, and the OSL
  testsuite folders that run one testshade command writing images (no
  printf, textures or debug modes), when both tools run them.

Shading time per point and pass is each tool's own timer of its shading
loop (testshade --runstats' "Run", osl-run --stats' "shading") at N passes
minus that at 1 pass (best of the rounds each), the two tools interleaved
shader by shader; N is --passes or more, so that OSL's N passes take about
0.5 s. The "wall" column is the same difference of whole-process times: it
was the measure until testshade's start-up (loading LLVM and clang) was
seen to take 0.65 s in one run and 0.87 s in the next of the same one-pass
command, as much as 8 passes of a 100 ns shader at 512x512, while its Run
timer moved by 0.02 s. Compile time: osl-run's source-to-kernel (--stats, no
kernel cache; the noise routines of the prebuilt library linked, as OSL
links its batched library compiled when it was built; "all compiled":
without the prebuilt library either, every noise routine compiled) against OSL's "Runtime optimization cost" (testshade
--runstats; OSL prints it to 10 ms) and against OSL's first-pass overhead
(testshade's Run time at 1 pass minus one pass), which has 0.1 ms
resolution. Prints each ratio (osl-run / OSL: below 1 is faster), their
geometric mean and the worst. Timings depend on the machine: read the
ratios, measured side by side in one run. Not a test.
"""
import argparse
import glob
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OSL_RUN = os.path.join(ROOT, "build", "bin", "osl-run")
SUITE = os.path.join(os.path.dirname(ROOT), "shared", "osl-testsuite")
OUTPUT_DECL = re.compile(
    r"\boutput\s+(?:float|int|color|point|vector|normal|matrix)\s+(\w+)\s*(?!\[)[=,)]")
# Tests whose time is not shading: text output, texture files, debug modes.
SKIP_SOURCE = re.compile(r"\b(printf|fprintf|texture|texture3d|environment|gettextureinfo|"
                         r"pointcloud_\w+|trace|getmessage|warning|error)\s*\(")


class Case:
    def __init__(self, name, src, args, folder, cwd=None):
        self.name, self.src, self.args, self.folder = name, src, args, folder
        self.cwd = cwd or folder


def host_width():
    with open("/proc/cpuinfo") as f:
        return 16 if "avx512f" in f.read() else 8


def outputs_of(src):
    with open(src, errors="replace") as f:
        text = re.sub(r"/\*.*?\*/|//[^\n]*", " ", f.read(), flags=re.S)
    return OUTPUT_DECL.findall(text)


def project_cases():
    cases = []
    for pattern in ("shaders/*.osl", "conformance/perf/*.osl", "bench/shaders/*.osl"):
        for src in sorted(glob.glob(os.path.join(ROOT, pattern))):
            outs = outputs_of(src)
            if not outs:
                continue
            args = []
            for o in outs:
                args += ["-o", o, o + ".exr"]
            name = os.path.relpath(src, ROOT)[:-4]
            # Conformance shaders name textures from conformance/, the
            # others from the repository root.
            cwd = os.path.join(ROOT, "conformance") if name.startswith("conformance/") else ROOT
            cases.append(Case(name, src, args, os.path.dirname(src), cwd=cwd))
    return cases


def suite_cases(suite):
    """Folders with one testshade command that writes images."""
    cases = []
    for run_py in sorted(glob.glob(os.path.join(suite, "*", "run.py"))):
        folder = os.path.dirname(run_py)
        with open(run_py) as f:
            text = f.read()
        calls = re.findall(r'testshade\s*\(\s*"([^"]*)"\s*\)', text)
        if len(calls) != 1 or " -o " not in " " + calls[0] or re.search(
                r"--?(debug|layer|shader|connect|group|param\s+\S+\s+\S+\s+\S+\s+\S+)", calls[0]):
            continue
        tokens = shlex.split(calls[0])
        shader = [t for i, t in enumerate(tokens) if not t.startswith("-")
                  and (i == 0 or tokens[i - 1] not in ("-g", "-od", "-o", "-param", "--param"))
                  and (i < 2 or tokens[i - 2] not in ("-o", "-param", "--param"))]
        if not shader:
            continue
        name = shader[-1]
        srcs = [os.path.join(folder, name + ".osl")] + [
            os.path.normpath(os.path.join(folder, p))
            for p in re.findall(r'oslc\s*\(\s*"([^"]+\.osl)"', text)
            if os.path.basename(p)[:-4] == name]
        src = next((s for s in srcs if os.path.exists(s)), None)
        if not src:
            continue
        with open(src, errors="replace") as f:
            if SKIP_SOURCE.search(f.read()):
                continue
        args, i = [], 0
        while i < len(tokens):
            t = tokens[i]
            if t == "-g":
                i += 3
                continue
            if t == "-od":
                i += 2
                continue
            if t == "-o":
                # The test's own file name, as .exr (an output may be asked
                # for twice, into two files).
                args += ["-o", tokens[i + 1], os.path.splitext(tokens[i + 2])[0] + ".exr"]
                i += 3
                continue
            if t != name:
                args.append(t)
            i += 1
        cases.append(Case("testsuite/" + os.path.basename(folder), src, args, folder))
    return cases


def wall(cmd, cwd, env=None):
    start = time.perf_counter()
    p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    return time.perf_counter() - start, p


class Tools:
    def __init__(self, a, work):
        self.a, self.work = a, work
        self.env = dict(os.environ)
        lib = os.path.join(a.osl, "lib")
        self.env["LD_LIBRARY_PATH"] = lib + ":" + self.env.get("LD_LIBRARY_PATH", "")
        self.env["TESTSHADE_BATCH_SIZE"] = str(a.width)
        self.testshade = os.path.join(a.osl, "bin", "testshade")
        self.oslc = os.path.join(a.osl, "bin", "oslc")

    def dir_of(self, case):
        d = os.path.join(self.work, case.name.replace("/", "_"))
        os.makedirs(d, exist_ok=True)
        return d

    def compile_oso(self, case):
        d = self.dir_of(case)
        name = os.path.basename(case.src)[:-4]
        p = subprocess.run([self.oslc, "-q", "-I" + case.folder, "-o",
                            os.path.join(d, name + ".oso"), case.src],
                           cwd=d, env=self.env, capture_output=True, text=True)
        return p.returncode == 0, p.stderr.strip().splitlines()[:1]

    def outputs(self, case):
        """case.args with each image written in the case's work directory."""
        args, d = list(case.args), self.dir_of(case)
        for i in range(len(args) - 2):
            if args[i] == "-o":
                args[i + 2] = os.path.join(d, args[i + 2])
        return args

    # stats: compile statistics (osl-run compiles afresh, --no-cache);
    # timers: only each tool's own timer of its shading loop printed
    # (testshade's "Run", osl-run's "shading"), which changes no work.
    def osl_cmd(self, case, res, passes, stats=False, timers=False):
        name = os.path.join(self.dir_of(case), os.path.basename(case.src)[:-4])
        return ([self.testshade, "--batched", "-t", "1", "-g", str(res), str(res),
                 "--iters", str(passes)] + (["--runstats"] if stats or timers else []) +
                self.outputs(case) + [name])

    def ours_cmd(self, case, res, passes, stats=False, timers=False):
        return ([OSL_RUN, "--width", str(self.a.width), "-t", "1", "-g", str(res), str(res),
                 "--iters", str(passes), "-I", case.folder] +
                (["--stats", "--no-cache"] if stats else ["--stats"] if timers else []) +
                self.outputs(case) + [case.src])

    def run(self, which, case, res, passes, stats=False, prebuilt=True, timers=False):
        if which == "osl":
            return wall(self.osl_cmd(case, res, passes, stats, timers), case.cwd, self.env)
        env = self.env
        if not prebuilt:
            env = dict(env, OSL_MLIR_NO_PREBUILT_LIBRARY="1")
        return wall(self.ours_cmd(case, res, passes, stats, timers), case.cwd, env)


def osl_opt_ms(stdout):
    m = re.search(r"Runtime optimization cost: ([0-9.]+)s", stdout)
    return float(m.group(1)) * 1e3 if m else float("nan")


def osl_run_ms(stdout):
    m = re.search(r"^Run\s*: ([0-9.]+)s", stdout, re.M)
    return float(m.group(1)) * 1e3 if m else float("nan")


def our_shading_ms(stderr):
    m = re.search(r"^  shading\s+([0-9.]+) ms$", stderr, re.M)
    return float(m.group(1)) if m else float("nan")


def loop_seconds(which, run):
    """The tool's own timer of its shading loop, in seconds (NaN if absent)."""
    ms = osl_run_ms(run.stdout) if which == "osl" else our_shading_ms(run.stderr)
    return ms / 1e3


def our_compile_ms(run):
    """Source-to-kernel time of a --stats run; NaN if the run failed or
    printed no stages (so that it cannot pass for a free compile)."""
    total, stages = 0.0, 0
    for m in re.finditer(r"^  (\S[^\n]*?)\s+([0-9.]+) ms$", run.stderr, re.M):
        if m.group(1) not in ("shading", "write images", "total"):
            total += float(m.group(2))
            stages += 1
    if run.returncode != 0 or stages == 0:
        print("  note: osl-run --stats gave no compile time (exit %d): %s" % (
            run.returncode, (run.stderr.strip().splitlines() or [""])[-1]), flush=True)
        return float("nan")
    return total


def geomean(xs):
    xs = [x for x in xs if x > 0 and math.isfinite(x)]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--osl", default=os.path.expanduser("~/.cache/osl-reference"))
    ap.add_argument("--width", type=int, default=host_width())
    ap.add_argument("--res", type=int, default=512)
    ap.add_argument("--passes", type=int, default=11)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--only", default="")
    ap.add_argument("--skip", default="", help="leave out shaders matching this regex")
    ap.add_argument("--no-testsuite", action="store_true")
    ap.add_argument("--suite", default=SUITE)
    a = ap.parse_args()
    if not os.path.exists(os.path.join(a.osl, "bin", "testshade")):
        sys.exit("no testshade in %s/bin: run ../shared/tools/build-osl-reference.sh" % a.osl)
    if not os.path.exists(OSL_RUN):
        sys.exit("no %s: build the project first" % OSL_RUN)
    work = tempfile.mkdtemp(prefix="vs-osl-")
    tools = Tools(a, work)
    cases = project_cases()
    if not a.no_testsuite and os.path.isdir(a.suite):
        cases += suite_cases(a.suite)
    cases = [c for c in cases if re.search(a.only, c.name) and not (a.skip and re.search(a.skip, c.name))]

    print("osl-run --width %d against testshade --batched (batch %d), 1 thread, %dx%d, "
          "shading = each tool's own shading-loop timer, (N passes - 1 pass) / (N - 1), "
          "N >= %d, best of %d interleaved rounds"
          % (a.width, a.width, a.res, a.res, a.passes, a.rounds), flush=True)
    runnable = []
    for c in cases:
        ok, err = tools.compile_oso(c)
        why = None
        if not ok:
            why = "oslc: " + " ".join(err)
        else:
            for which in ("osl", "ours"):
                _, p = tools.run(which, c, 16, 1)
                if p.returncode != 0:
                    lines = (p.stderr or p.stdout).strip().splitlines()
                    why = "%s fails: %s" % (which, lines[-1] if lines else "rc %d" % p.returncode)
                    break
        if why:
            print("  skip %-40s %s" % (c.name, why[:100]), flush=True)
        else:
            runnable.append(c)

    # Passes per shader: enough that the timed difference is about 0.5 s
    # of OSL's shading (at least --passes), so cheap shaders are not lost
    # in the noise of process start-up.
    passes = {}
    for c in runnable:
        t1, _ = tools.run("osl", c, a.res, 1)
        tn, _ = tools.run("osl", c, a.res, a.passes)
        per_pass = max(tn - t1, 1e-3) / (a.passes - 1)
        passes[c.name] = int(min(max(a.passes, 0.5 / per_pass + 1), 401))
    one = {(c.name, w): float("inf") for c in runnable for w in ("osl", "ours")}
    many = dict(one)
    loop_one, loop_many = dict(one), dict(one)
    opt = {c.name: float("inf") for c in runnable}
    first = dict(opt)
    ours_compile = dict(opt)
    ours_all = dict(opt)
    # The kernel cache holds each timed kernel before the timing starts (its
    # key has the grid's size): a first run compiles, the later ones load.
    for c in runnable:
        tools.run("ours", c, a.res, 1)
    for _ in range(a.rounds):
        for c in runnable:
            for which in ("osl", "ours"):
                t1, p1 = tools.run(which, c, a.res, 1, timers=True)
                tn, pn = tools.run(which, c, a.res, passes[c.name], timers=True)
                one[c.name, which] = min(one[c.name, which], t1)
                many[c.name, which] = min(many[c.name, which], tn)
                loop_one[c.name, which] = min(loop_one[c.name, which], loop_seconds(which, p1))
                loop_many[c.name, which] = min(loop_many[c.name, which], loop_seconds(which, pn))
                # Compile statistics from a run of their own: printing them
                # (and osl-run's --no-cache) must not enter the timed runs.
                _, p1 = tools.run(which, c, a.res, 1, stats=True)
                if which == "osl":
                    opt[c.name] = min(opt[c.name], osl_opt_ms(p1.stdout))
                    first[c.name] = min(first[c.name], osl_run_ms(p1.stdout))
                else:
                    ours_compile[c.name] = min(ours_compile[c.name], our_compile_ms(p1))
                    # Again compiling every noise routine.
                    _, pa = tools.run(which, c, 16, 1, stats=True, prebuilt=False)
                    ours_all[c.name] = min(ours_all[c.name], our_compile_ms(pa))

    # A shader whose every --stats run failed has no compile time (NaN,
    # left out of the means and said so), not infinity.
    for table in (ours_compile, ours_all):
        for name, ms in table.items():
            if not math.isfinite(ms):
                table[name] = float("nan")
                print("  note: no compile time for %s" % name, flush=True)

    points = a.res * a.res
    print("\n%-40s %9s %9s %7s %7s   %9s %9s %9s %7s %7s %9s %7s" % (
        "shader", "OSL ns", "ours ns", "ratio", "wall", "OSL opt", "OSL 1st", "ours jit",
        "/opt", "/1st", "all comp", "/opt"))
    ratios, cratios, fratios, wratios, wall_ratios = [], [], [], [], []
    for c in runnable:
        def per_point(t_many, t_one):
            t = (t_many - t_one) / (passes[c.name] - 1) / points * 1e9
            return max(t, 0) if math.isfinite(t) else float("nan")
        ns = {w: per_point(loop_many[c.name, w], loop_one[c.name, w]) for w in ("osl", "ours")}
        wall_ns = {w: per_point(many[c.name, w], one[c.name, w]) for w in ("osl", "ours")}
        ratio = ns["ours"] / ns["osl"] if ns["osl"] > 0 else float("nan")
        wall_ratio = wall_ns["ours"] / wall_ns["osl"] if wall_ns["osl"] > 0 else float("nan")
        wall_ratios.append(wall_ratio)
        pass_ms = ns["osl"] * points / 1e6
        first_cost = first[c.name] - pass_ms
        cr = ours_compile[c.name] / opt[c.name] if opt[c.name] > 0 else float("nan")
        fr = ours_compile[c.name] / first_cost if first_cost > 0 else float("nan")
        wr = ours_all[c.name] / opt[c.name] if opt[c.name] > 0 else float("nan")
        ratios.append(ratio)
        cratios.append(cr)
        fratios.append(fr)
        wratios.append(wr)
        print("%-40s %9.2f %9.2f %7.2f %7.2f   %9.1f %9.1f %9.1f %7.2f %7.2f %9.1f %7.2f" % (
            c.name, ns["osl"], ns["ours"], ratio, wall_ratio, opt[c.name], first_cost,
            ours_compile[c.name], cr, fr, ours_all[c.name], wr), flush=True)
    if runnable:
        worst = max(((r, c.name) for r, c in zip(ratios, runnable) if math.isfinite(r)),
                    default=(float("nan"), "none"))
        print("\nshading: geometric mean %.2fx OSL over %d shaders, worst %.2fx (%s), "
              "%d slower than OSL" % (geomean(ratios), len(ratios), worst[0], worst[1],
                                      sum(r > 1 for r in ratios)))
        print("shading by whole-process time instead: geometric mean %.2fx, worst %.2fx, "
              "%d slower than OSL" % (geomean(wall_ratios),
                                      max((x for x in wall_ratios if math.isfinite(x)),
                                          default=float("nan")),
                                      sum(r > 1 for r in wall_ratios)))
        print("compile: geometric mean %.2fx OSL's optimization cost, %.2fx its first-pass "
              "overhead; worst %.2fx / %.2fx; %d of %d at most 0.5x" % (
                  geomean(cratios), geomean(fratios),
                  max((x for x in cratios if math.isfinite(x)), default=float("nan")),
                  max((x for x in fratios if math.isfinite(x)), default=float("nan")),
                  sum(x <= 0.5 for x in cratios), len(cratios)))
        print("compile without the prebuilt library: geometric mean %.2fx OSL's optimization "
              "cost, worst %.2fx; %d of %d at most 0.5x" % (
                  geomean(wratios),
                  max((x for x in wratios if math.isfinite(x)), default=float("nan")),
                  sum(x <= 0.5 for x in wratios), len(wratios)))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
