#!/usr/bin/env python3
"""Runs OSL's own testsuite with osl-run in place of testshade and testrender.

Each test folder of the suite (../shared/osl-testsuite in CI) has a run.py
that builds its commands from helper functions (testshade, testrender, oslc,
oslinfo, oiiotool, ...) and names the outputs that are compared with ref/.
This runner defines those helpers so that testshade becomes `osl-run`,
testrender becomes `osl-run --scene`, and oslc becomes `osl-run --check`
(printing oslc's "Compiled X -> Y" line when the shader compiles), then
judges the outputs the way OSL's runtest.py does: text files exactly (after
the test's filter_re), images with oiiotool --diff and the test's
failthresh/failpercent/hardfail, matching ref/OUT or any other ref/ file of
the same extension. Tests without ref/ (the "-reg" tests) are judged as
OSL judges them in regression mode: their outputs at width 1 are the
baseline for the widest width.

Two additions, both from the issue that asked for this runner:
  - a test that only compiles (no testshade/testrender) and whose reference
    output is oslc's errors passes when osl-run rejects the shader with an
    error on one of the same lines;
  - an expected-failures list (one `NAME  reason` per line) makes the run
    fail when a test outside it fails or a listed test passes.
"""
import argparse
import concurrent.futures
import difflib
import filecmp
import glob
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

IMAGE_EXTENSIONS = (".tif", ".exr")
COMMAND_TIMEOUT = 120  # seconds; a shader that never ends fails its test
CWD_LOCK = threading.Lock()  # run.py is evaluated in its test's folder


class Test:
    def __init__(self, name, suite):
        self.name = name
        self.src = os.path.join(suite, name)
        with open(os.path.join(self.src, "run.py")) as f:
            self.script = f.read()
        code = "\n".join(l for l in self.script.splitlines()
                         if not l.lstrip().startswith("#"))
        # run.py calls them as functions, with or without a space before
        # the parenthesis ("testshade (" in a fifth of the folders).
        self.uses_testshade = re.search(r"\btestshade\s*\(", code) is not None
        self.uses_testrender = re.search(r"\btestrender\s*\(", code) is not None
        self.regression = not os.path.isdir(os.path.join(self.src, "ref"))

    @property
    def runs_shaders(self):
        return self.uses_testshade or self.uses_testrender


class Context:
    """What run.py sees: runtest.py's variables and helper functions."""

    def __init__(self, test, osl_run, width, workdir):
        self.test, self.osl_run, self.width, self.workdir = test, osl_run, width, workdir
        self.runtest_impl = None  # set once the commands are known
        # The -D/-U/-I the last oslc call used: osl-run compiles the source
        # again when it shades, so it needs them too.
        self.compile_flags = []

    def namespace(self):
        ns = {
            "command": "", "outputs": ["out.txt"], "failureok": 0,
            "failthresh": 0.004, "hardfail": 0.01, "failpercent": 0.02,
            "failrelative": 0.001, "allowfailures": 0,
            "idiff_program": "oiiotool", "idiff_postfilecmd": "",
            "filter_re": None, "cleanup_on_success": False, "oslcargs": "-Wall",
            "compile_osl_files": True, "splitsymbol": ";",
            "srcdir": self.workdir + "/", "tmpdir": self.workdir,
            "test_source_dir": self.test.src, "refdir": "ref/",
            "OSL_TESTSUITE_ROOT": os.path.dirname(self.test.src),
            "OSL_BUILD_DIR": "..", "OSL_SOURCE_DIR": "../../..",
            "OSL_TESTSUITE_DIR": os.path.dirname(self.test.src),
            "OpenImageIO_ROOT": None, "redirect": REDIRECT,
            "mytest": self.test.name, "pythonbin": sys.executable,
            "image_extensions": [".tif", ".tx", ".exr", ".jpg", ".png",
                                 ".rla", ".dpx", ".iff", ".psd"],
            "os": os, "sys": sys, "glob": glob, "re": re, "shutil": shutil,
            "platform": __import__("platform"),
        }
        ns.update({
            "runtest": lambda command, outputs=None, *a, **k:
                self.runtest_impl(command, outputs if outputs is not None else ns["outputs"]),
            "testshade": self.testshade, "testrender": self.testrender,
            "testoptix": self.unsupported("testoptix"),
            "oslc": lambda args: self.oslc(args, ns["oslcargs"]),
            "oslinfo": self.oslinfo,
            "oiiotool": self.oiiotool, "maketx": self.maketx,
            "run_app": self.run_app, "osl_app": lambda app: app + " ",
            "oiio_app": lambda app: app + " ",
            "make_relpath": lambda p, start=os.curdir: os.path.relpath(p, start),
            "oiiodiff": lambda a, b, extraargs="", silent=True, concat=True:
                image_diff_command(a, b, ns, extraargs) + (" ;\n" if concat else ""),
        })
        return ns

    def osl_run_cmd(self):
        cmd = shlex.quote(self.osl_run)
        if self.width:
            cmd += " --width %d" % self.width
        return cmd

    def testshade(self, args):
        # testshade shades one point unless -g says otherwise.
        flags = "".join(" " + shlex.quote(f) for f in self.compile_flags)
        # -w: oslc has reported the warnings already; testshade loads
        # compiled shaders and prints none. --keep-going: testshade reports
        # a texture it cannot read and still exits 0.
        return (self.osl_run_cmd() + " -w --keep-going" + flags + " -g 1 1 " + args +
                REDIRECT + " ;\n")

    def testrender(self, args):
        words = shlex.split(args)
        files = [w for w in words if w.endswith(".xml") or
                 os.path.splitext(w)[1] in IMAGE_EXTENSIONS + (".png",)]
        rest = [w for w in words if w not in files]
        scene = next((w for w in files if w.endswith(".xml")), "scene.xml")
        out = next((w for w in files if not w.endswith(".xml")), "out.exr")
        return (self.osl_run_cmd() + " -w --keep-going --scene " + shlex.quote(scene) + " -o " +
                shlex.quote(out) + " " + " ".join(shlex.quote(w) for w in rest) +
                REDIRECT + " ;\n")

    def oslc(self, args, oslcargs):
        # oslc prints "Compiled A.osl -> A.oso" on success and its errors
        # otherwise; osl-run --check compiles without shading.
        words = shlex.split(oslcargs + " " + args)
        sources = [w for w in words if w.endswith(".osl")]
        flags = [w for w in words if w.startswith(("-D", "-I", "-U"))]
        # Make dependencies (-M, -MM, -MD, -MMD, -MF FILE, -MT TARGET) pass
        # through; -MF and -MT may take the next word.
        deps = []
        for i, w in enumerate(words):
            if w in ("-MF", "-MT") and i + 1 < len(words):
                deps += [w, words[i + 1]]
            elif w.startswith("-M"):
                deps.append(w)
        # -M and -MM print the dependencies instead of compiling.
        quiet = "-q" in words or "-M" in words or "-MM" in words
        if sources:
            self.compile_flags = flags
        cmds = ""
        for src in sources:
            base = os.path.splitext(os.path.basename(src))[0]
            if os.path.dirname(src):
                # oslc leaves X.oso in the current folder, where testshade
                # then finds it: the source goes there for osl-run.
                cmds += "cp %s . ;\n" % shlex.quote(src)
            werror = " -Werror" if "-Werror" in words else ""
            check = (self.osl_run_cmd() + " --check" + werror + " " +
                     " ".join(shlex.quote(f) for f in flags + deps) + " " + shlex.quote(src))
            # oslc names X.oso after the shader the file declares; a shader
            # whose name is not its file's is found by that name (osl-run
            # takes an extensionless file as the shader's source).
            name = (declared_shader_name(os.path.join(self.workdir, src)) or
                    preprocessed_shader_name(self.osl_run, flags, self.workdir, src) or base)
            also = "" if name == base else " && cp %s %s" % (shlex.quote(src), shlex.quote(name))
            compiled = "" if quiet else " && echo %s >> out.txt" % shlex.quote(
                "Compiled %s -> %s.oso" % (src, name))
            # What osl-run prints (-M's dependencies) comes after oslc's
            # "Compiled" line.
            cmds += ("%s > oslc.stdout 2>>out.txt%s%s && cat oslc.stdout >> out.txt ;\n" %
                     (check, also, compiled))
        return cmds

    def oslinfo(self, args):
        return self.osl_run_cmd() + " --info " + args + REDIRECT + " ;\n"

    def oiiotool(self, args, silent=False):
        return "oiiotool " + args + ("" if silent else REDIRECT) + " ;\n"

    def maketx(self, args):
        return "maketx " + args + REDIRECT + " ;\n"

    def run_app(self, app, silent=False, concat=True):
        return app + ("" if silent else REDIRECT) + (" ;\n" if concat else "")

    def unsupported(self, name):
        return lambda *a, **k: "echo '%s is not supported' >&2 ; false ;\n" % name


REDIRECT = " >> out.txt 2>>out.txt "

PYTHON_MODULES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python")

SHADER_DECL = re.compile(r"\b(?:shader|surface|displacement|volume|light)\s+([A-Za-z_]\w*)\s*[(\[]")


def declared_shader_name(path):
    """The name of the shader a source file declares, or None."""
    try:
        with open(path, errors="replace") as f:
            text = f.read()
    except OSError:
        return None
    text = re.sub(r"/\*.*?\*/|//[^\n]*", " ", text, flags=re.S)
    m = SHADER_DECL.search(text)
    return m.group(1) if m else None


def preprocessed_shader_name(osl_run, flags, workdir, src):
    """The shader's name as osl-run --info sees it, after the preprocessor:
    for a name built by a macro in an included header (OSL's "xmacro" tests)."""
    try:
        info = subprocess.run([osl_run, "--info"] + flags + [src], cwd=workdir,
                              capture_output=True, text=True, timeout=COMMAND_TIMEOUT)
    except (OSError, subprocess.TimeoutExpired):
        return None
    m = re.match(r'\w+ "([A-Za-z_]\w*)"', info.stdout)
    return m.group(1) if info.returncode == 0 and m else None


# osl-imgdiff (beside osl-run): passes images whose every value is within
# the failing threshold, which idiff passes too, in milliseconds; idiff
# (0.7 s a call, most of it loading OpenImageIO) judges the others.
IMGDIFF = None


def image_diff_command(a, b, ns, extraargs=""):
    thresh = ("-fail %s -failpercent %s -hardfail %s -warn %s -warnpercent %s" %
              (ns["failthresh"], ns["failpercent"], ns["hardfail"],
               2 * ns["failthresh"], ns["failpercent"]))
    if ns["idiff_program"] == "idiff":
        thresh += " -failrelative %s -allowfailures %s" % (
            ns["failrelative"], ns["allowfailures"])
        full = "idiff -a %s %s %s %s" % (thresh, extraargs, a, b)
    else:
        full = "oiiotool -a %s %s %s %s --diff" % (thresh, extraargs, a, b)
    if not IMGDIFF or extraargs.strip():
        return full
    quick = "%s --fail %s %s %s >/dev/null 2>&1" % (
        shlex.quote(IMGDIFF), min(float(ns["failthresh"]), float(ns["hardfail"])), a, b)
    return "{ %s || %s ; }" % (quick, full)


def run_shell(cmd, cwd):
    """Runs one sub-command in its own process group, bounded in time."""
    proc = subprocess.Popen(cmd, shell=True, cwd=cwd, start_new_session=True,
                            stdout=subprocess.DEVNULL if "out.txt" in cmd else None)
    try:
        return proc.wait(timeout=COMMAND_TIMEOUT)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        with open(os.path.join(cwd, "out.txt"), "a") as f:
            f.write("[runner] timed out after %d s: %s\n" % (COMMAND_TIMEOUT, cmd))
        return -1


def text_matches(out, ref, filter_re):
    def lines(path):
        with open(path, errors="replace") as f:
            ls = f.readlines()
        if filter_re:
            filt = re.compile(filter_re)
            ls = [l for l in ls if filt.match(l) is not None]
        return ls
    return not list(difflib.unified_diff(lines(ref), lines(out)))


ERROR_LINE = re.compile(r"^([^\s:]+\.osl?|[^\s:]+\.h):(\d+):(?:\d+:)?\s*error")


def error_lines(path):
    with open(path, errors="replace") as f:
        return {(os.path.basename(m.group(1)), int(m.group(2)))
                for m in map(ERROR_LINE.match, f) if m}


def prepare(test, work_root):
    work = os.path.join(work_root, test.name)
    if os.path.exists(work):
        shutil.rmtree(work)
    os.makedirs(work)
    for link in ("ref", "src"):
        if os.path.exists(os.path.join(test.src, link)):
            os.symlink(os.path.join(test.src, link), os.path.join(work, link))
    os.symlink(test.src, os.path.join(work, "data"))
    for pattern in ("*.osl", "*.h", "*.oslgroup", "*.xml"):
        for f in glob.glob(os.path.join(test.src, pattern)):
            shutil.copyfile(f, os.path.join(work, os.path.basename(f)))
    return work


def build_commands(test, ctx, work):
    ns = ctx.namespace()
    with CWD_LOCK:
        old = os.getcwd()
        os.chdir(work)  # run.py may glob or test files relative to the test
        try:
            exec(compile(test.script, os.path.join(test.src, "run.py"), "exec"), ns)
        finally:
            os.chdir(old)
    command = ns["command"]
    if ns["compile_osl_files"]:
        compiles = "".join(ns["oslc"](f) for f in
                           sorted(os.path.basename(p) for p in glob.glob(os.path.join(work, "*.osl"))))
        command = compiles + command
    outputs = list(ns["outputs"])
    for extra in ("out.exr", "out.tif"):
        if os.path.exists(os.path.join(test.src, "ref", extra)) and extra not in outputs:
            outputs.append(extra)
    return command, outputs, ns


def run_commands(command, ns, work):
    open(os.path.join(work, "out.txt"), "w").close()
    for sub in command.split(ns["splitsymbol"]):
        sub = sub.strip()
        if not sub:
            continue
        if run_shell(sub, work) != 0 and not ns["failureok"]:
            return "%s failed: %s" % (os.path.basename(shlex.split(sub)[0]), first_error(work))
    return None


def first_error(work):
    """The first error the commands wrote to out.txt, for the reason."""
    with open(os.path.join(work, "out.txt"), errors="replace") as f:
        for line in f:
            if "error" in line.lower() or "timed out" in line:
                return line.strip()[:200]
    return "(no message)"


def judge_outputs(test, outputs, ns, work, ref_dir):
    for out in outputs:
        path = os.path.join(work, out)
        if not os.path.exists(path):
            return "no output %s" % out
        ext = os.path.splitext(out)[1]
        candidates = [os.path.join(ref_dir, out)]
        if ref_dir.endswith("ref"):
            candidates += sorted(glob.glob(os.path.join(ref_dir, "*" + ext)))
        ok = False
        for ref in candidates:
            if not os.path.exists(ref):
                continue
            if ext in IMAGE_EXTENSIONS:
                ok = subprocess.call(image_diff_command(path, ref, ns), shell=True, cwd=work,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL) == 0
            elif ext == ".txt":
                ok = text_matches(path, ref, ns["filter_re"])
            else:
                ok = filecmp.cmp(path, ref)
            if ok:
                break
        if not ok:
            if ext == ".txt":
                return "%s differs from ref (first difference: %s)" % (out, first_difference(path, ref_dir, out))
            return "%s does not match ref" % out
    return None


def first_difference(path, ref_dir, out):
    ref = os.path.join(ref_dir, out)
    if not os.path.exists(ref):
        return "no reference"
    with open(path, errors="replace") as a, open(ref, errors="replace") as b:
        ours, theirs = a.read().splitlines(), b.read().splitlines()
    for i, (x, y) in enumerate(zip(ours, theirs)):
        if x != y:
            return "line %d %r, expected %r" % (i + 1, x[:80], y[:80])
    return "%d lines, expected %d" % (len(ours), len(theirs))


def oslc_error_test_passes(test, work):
    """An oslc-only test whose reference is oslc's errors: osl-run must
    reject the shader with an error on one of the reference's lines."""
    ref = os.path.join(test.src, "ref", "out.txt")
    if test.runs_shaders or not os.path.exists(ref):
        return False
    expected = error_lines(ref)
    return bool(expected) and bool(error_lines(os.path.join(work, "out.txt")) & expected)


def run_test(test, osl_run, width, work_root):
    """Returns (status, reason): PASS, FAIL or SKIP."""
    try:
        work = prepare(test, work_root)
        if test.regression:
            # OSL's regression mode: the baseline run, then the batched run
            # compared with it. Here width 1 is the baseline.
            ctx = Context(test, osl_run, 1, work)
            command, outputs, ns = build_commands(test, ctx, work)
            err = run_commands(command, ns, work)
            if err:
                return "FAIL", "baseline (width 1): " + err
            base = os.path.join(work, "baseline")
            os.makedirs(base, exist_ok=True)
            for out in outputs:
                if os.path.exists(os.path.join(work, out)):
                    shutil.move(os.path.join(work, out), os.path.join(base, out))
            ctx = Context(test, osl_run, width or 16, work)
            command, outputs, ns = build_commands(test, ctx, work)
            err = run_commands(command, ns, work)
            if err:
                return "FAIL", err
            err = judge_outputs(test, outputs, ns, work, base)
            return ("FAIL", err) if err else ("PASS", "regression: widest width equals width 1")
        ctx = Context(test, osl_run, width, work)
        command, outputs, ns = build_commands(test, ctx, work)
        ref_dir = os.path.join(work, "ref")
        failures = []

        def runtest(command, outputs=outputs, *args, **kwargs):
            # runtest.py's own: run the commands, judge the outputs, 0 if
            # they pass. A run.py may wrap it to run several variants.
            err = run_commands(command, ns, work) or \
                judge_outputs(test, outputs, ns, work, ref_dir)
            if err:
                failures.append(err)
            return 1 if err else 0

        ctx.runtest_impl = runtest
        # A run.py may replace runtest (keeping the original to call):
        # runtest.py then calls the replacement, as here.
        ns["runtest"](command, outputs)
        err = failures[0] if failures else None
        if err is None:
            return "PASS", ""
        if oslc_error_test_passes(test, work):
            return "PASS", "rejected with an error on the reference's line"
        return "FAIL", err
    except Exception as e:  # a run.py this runner cannot evaluate
        return "FAIL", "runner: %s: %s" % (type(e).__name__, e)


def read_expected(path):
    expected = {}
    if path and os.path.exists(path):
        with open(path) as f:
            for line in f:
                line = line.split("#", 1)[0].rstrip() if line.lstrip().startswith("#") else line.rstrip()
                if not line.strip():
                    continue
                name, _, reason = line.strip().partition(" ")
                expected[name] = reason.strip()
    return expected


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--suite", required=True, help="OSL's testsuite folder")
    ap.add_argument("--osl-run", required=True)
    ap.add_argument("--width", type=int, default=0, help="osl-run --width (default: its own)")
    ap.add_argument("--expected", default=os.path.join(here, "expected-failures.txt"))
    ap.add_argument("--work", help="where tests run (default: a temporary folder)")
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    ap.add_argument("-j", type=int, default=2)
    ap.add_argument("--write-expected", help="write the failures found to this file")
    ap.add_argument("tests", nargs="*", help="only these tests")
    args = ap.parse_args()

    suite = os.path.abspath(args.suite)
    if not os.path.isdir(suite):
        print("SKIP: no OSL testsuite at %s" % suite)
        return 0
    osl_run = os.path.abspath(args.osl_run)
    global IMGDIFF
    imgdiff = os.path.join(os.path.dirname(osl_run), "osl-imgdiff")
    IMGDIFF = imgdiff if os.access(imgdiff, os.X_OK) else None
    # Tests that `import oslquery` get osl-mlir's (python/oslquery.py),
    # which asks this osl-run.
    os.environ["OSLMLIR_OSL_RUN"] = osl_run
    os.environ["PYTHONPATH"] = os.pathsep.join(
        [PYTHON_MODULES] + [p for p in [os.environ.get("PYTHONPATH")] if p])
    # oiiotool reads "shader.oso?RES=64" through osl-mlir's osl.imageio.so.
    os.environ["OIIO_LIBRARY_PATH"] = os.pathsep.join(
        [os.path.join(os.path.dirname(os.path.dirname(osl_run)), "lib")] +
        [p for p in [os.environ.get("OIIO_LIBRARY_PATH")] if p])
    names = sorted(d for d in os.listdir(suite)
                   if os.path.exists(os.path.join(suite, d, "run.py")))
    if args.tests:
        unknown = [t for t in args.tests if t not in names]
        if unknown:
            print("error: no such test: " + " ".join(unknown), file=sys.stderr)
            return 2
        names = args.tests
    tests = [Test(n, suite) for n in names]
    expected = read_expected(args.expected)

    work_root = os.path.abspath(args.work) if args.work else tempfile.mkdtemp(prefix="osl-testsuite-")
    os.makedirs(work_root, exist_ok=True)
    if not os.path.exists(os.path.join(work_root, "common")):
        os.symlink(os.path.join(suite, "common"), os.path.join(work_root, "common"))

    results = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.j)) as pool:
        def timed(t):
            start = time.monotonic()
            status, reason = run_test(t, osl_run, args.width, work_root)
            return status, reason, time.monotonic() - start
        futures = {pool.submit(timed, t): t for t in tests}
        for fut in concurrent.futures.as_completed(futures):
            t = futures[fut]
            results[t.name] = fut.result()
    counts = {"PASS": 0, "FAIL": 0, "SKIP": 0}
    shader_counts = {"PASS": 0, "FAIL": 0, "SKIP": 0}
    unexpected_fail, unexpected_pass = [], []
    for t in tests:
        status, reason, seconds = results[t.name]
        counts[status] += 1
        if t.runs_shaders:
            shader_counts[status] += 1
        note = ""
        if status == "FAIL" and t.name not in expected:
            unexpected_fail.append(t.name)
            note = "  [not in the expected-failures list]"
        if status == "PASS" and t.name in expected:
            unexpected_pass.append(t.name)
            note = "  [listed as expected to fail: remove it from the list]"
        print("%s: %s%s (%.1f s)%s" % (status, t.name, (" - " + reason) if reason else "",
                                       seconds, note))

    if args.write_expected:
        with open(args.write_expected, "w") as f:
            f.write("# OSL testsuite tests osl-run is expected to fail, each with the reason.\n"
                    "# test/osl-testsuite/run_testsuite.py fails when a test outside this\n"
                    "# list fails or a listed test passes, so the list only shrinks.\n")
            for t in tests:
                status, reason, _ = results[t.name]
                if status == "FAIL":
                    f.write("%s  %s\n" % (t.name, reason))

    total = len(tests)
    ran = sum(shader_counts.values())
    print()
    print("folders that run shaders (testshade/testrender): %d, passed %d (%.1f%%)" %
          (ran, shader_counts["PASS"], 100.0 * shader_counts["PASS"] / max(1, ran)))
    print("all folders: %d passed, %d failed, %d skipped (of %d); expected failures listed: %d" %
          (counts["PASS"], counts["FAIL"], counts["SKIP"], total, len(expected)))
    if not args.keep and not args.work:
        shutil.rmtree(work_root, ignore_errors=True)
    if unexpected_fail or unexpected_pass:
        print("unexpected failures: %s" % (" ".join(unexpected_fail) or "none"))
        print("unexpected passes: %s" % (" ".join(unexpected_pass) or "none"))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
