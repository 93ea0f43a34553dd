#!/usr/bin/env python3
"""Random OSL shaders for the differential tester (osl-difftest).

  generate.py --seed S --count N --out DIR

Writes DIR/gen_<seed>.osl for seeds S .. S+N-1. Each shader is valid OSL
with divergent control flow: nested if/else on per-point conditions,
for/while/do-while loops whose trip counts differ per point (all bounded),
break and continue under varying conditions, a chain of user functions
(each may call the ones before it, so early returns nest several calls
deep) that return early at any depth, also from inside loops, write an
output parameter on some paths only and may exit(); exit() under a varying
condition in the shader and in a function called from parameter defaults
(one of them lockgeom=0, one possibly unused); struct and array locals,
the arrays indexed per point; outputs written on some paths only, uniform
loops with varying bodies, and library calls (math, noise, geometry). The
same seed always gives the same shader.

Outputs default to 0, the renderer's own initial value: where a parameter
default exits, OSL leaves an output's default unset or set depending on
whether its optimizer found the default overwritten, which no other
compiler can match.

Arguments never alias the output argument of the same call: OSL passes
every argument by reference, so aliasing would make the result depend on
evaluation order that the language does not pin down.
"""
import argparse
import os
import random

FLOAT_UNARY = ["sin", "cos", "sqrt", "abs", "floor", "exp", "log", "atan", "fabs",
               "ceil", "sign", "tanh", "inversesqrt", "cbrt", "erf"]
FLOAT_BINARY = ["min", "max", "pow", "fmod", "atan2", "step", "mod"]
NOISES = ["perlin", "uperlin", "cell", "simplex", "usimplex", "hash"]
HELPERS = 3  # helper0 .. helper2; helperK may call helperJ for J < K


class Scope:
    """What a block of code may read and write."""

    def __init__(self, readable, writable, ints, helpers, in_function):
        self.readable = readable    # float expressions that can be read
        self.writable = writable    # float lvalues that can be assigned
        self.out_args = out_args_of(writable)  # lvalues fit to pass as output
        self.ints = ints            # int variables in scope
        self.helpers = helpers      # helper functions callable from here
        self.in_function = in_function


def out_args_of(writable):
    # Plain variables and struct fields; a per-point array index is not an
    # lvalue OSL lets a call alias cleanly.
    return [w for w in writable if "[" not in w or w.endswith("[1]")]


class Gen:
    def __init__(self, rng, param_exit=True):
        self.r = rng
        self.param_exit = param_exit
        self.depth = 0
        self.loop_depth = 0
        self.counter = 0
        self.scope = None
        self.excluded = set()  # the output argument of the call being built

    def name(self, prefix):
        self.counter += 1
        return "%s%d" % (prefix, self.counter)

    # --- expressions ---------------------------------------------------------
    def leaf(self):
        r = self.r
        names = [f for f in self.scope.readable if f not in self.excluded]
        if r.random() < 0.15:
            return "%.3f" % r.uniform(-2, 2)
        arrays_free = not any(e.startswith("arr[") for e in self.excluded)
        if r.random() < 0.1 and "arr[0]" in self.scope.readable and arrays_free:
            return "arr[%s]" % self.index()
        return r.choice(names + ["u", "v"])

    def index(self):
        """A per-point index into a float[4] that is always in range."""
        r = self.r
        choices = ["clamp((int) (u * 4.0), 0, 3)", "clamp((int) (v * 5.0) - 1, 0, 3)"]
        choices += ["clamp(%s, 0, 3)" % i for i in self.scope.ints]
        return r.choice(choices)

    def fexpr(self, d=0):
        r = self.r
        choice = r.random()
        if d > 1 or choice < 0.3:
            return self.leaf()
        if choice < 0.45:
            op = r.choice(["+", "-", "*", "/"])
            return "(%s %s %s)" % (self.fexpr(d + 1), op, self.fexpr(d + 1))
        if choice < 0.65:
            return "%s(%s)" % (r.choice(FLOAT_UNARY), self.fexpr(d + 1))
        if choice < 0.78:
            return "%s(%s, %s)" % (r.choice(FLOAT_BINARY), self.fexpr(d + 1), self.fexpr(d + 1))
        if choice < 0.82:
            return 'noise("%s", %s * 3.0, %s)' % (r.choice(NOISES), self.fexpr(d + 1),
                                                 self.fexpr(d + 1))
        if choice < 0.92:
            return "length(vector(%s, %s, 1.0))" % (self.fexpr(d + 1), self.fexpr(d + 1))
        if choice < 0.96:
            return "clamp(%s, -3.0, 3.0)" % self.fexpr(d + 1)
        if not self.scope.ints:
            return "%.3f" % r.uniform(-2, 2)
        return "(float) %s" % r.choice(self.scope.ints)

    def cond(self):
        r = self.r
        a, b = self.fexpr(1), self.fexpr(1)
        c = "%s %s %s" % (a, r.choice(["<", ">", "<=", ">="]), b)
        if r.random() < 0.2:
            c = "(%s) %s (%s %s %.2f)" % (c, r.choice(["&&", "||"]), r.choice(["u", "v"]),
                                         r.choice(["<", ">"]), r.uniform(0, 1))
        return c

    def call(self, target, helper=None):
        """helperK(a, b, out) for `target += ...`, with `out` neither the
        target nor read anywhere else in the call."""
        r = self.r
        if helper is None:
            helper = r.choice(self.scope.helpers)
        out = r.choice([o for o in self.scope.out_args if o != target])
        self.excluded = {out}
        args = (self.fexpr(1), self.fexpr(1))
        self.excluded = set()
        return "helper%d(%s, %s, %s)" % (helper, args[0], args[1], out), out

    # --- statements ------------------------------------------------------------
    def block(self, indent, count=None):
        count = count if count is not None else self.r.randint(1, 3)
        return "".join(self.stmt(indent) for _ in range(count))

    def stmt(self, ind):
        r = self.r
        pad = "    " * ind
        kinds = ["assign", "assign", "assign", "out", "array"]
        if self.depth < 3:
            kinds += ["if", "if", "for", "while"]
            if self.scope.helpers:
                kinds += ["call", "call"]
        if self.loop_depth > 0:
            kinds += ["break", "continue"]
        if self.scope.in_function:
            kinds += ["return", "return"]
            if r.random() < 0.3:
                kinds += ["exit"]
        elif self.depth > 0:
            kinds += ["exit"]
        k = r.choice(kinds)
        if k == "assign":
            return "%s%s %s %s;\n" % (pad, r.choice(self.scope.writable),
                                     r.choice(["=", "+=", "*=", "-="]), self.fexpr())
        if k == "array":
            if "arr[0]" not in self.scope.writable:
                return "%sresult += %s;\n" % (pad, self.fexpr())
            return "%sarr[%s] = %s;\n" % (pad, self.index(), self.fexpr())
        if k == "out":
            if self.scope.in_function:
                return "%sresult += %s;\n" % (pad, self.fexpr())
            return "%s%s = %s;\n" % (pad, r.choice(["fa", "fb"]), self.fexpr())
        if k == "break":
            return "%sif (%s) break;\n" % (pad, self.cond())
        if k == "continue":
            return "%sif (%s) continue;\n" % (pad, self.cond())
        if k == "return":
            return "%sif (%s) return %s;\n" % (pad, self.cond(), self.fexpr())
        if k == "exit":
            return "%sif (%s) exit();\n" % (pad, self.cond())
        if k == "call":
            target = "result" if self.scope.in_function else "acc"
            text, out = self.call(target)
            return "%s%s += %s;\n" % (pad, target, text)
        self.depth += 1
        try:
            if k == "if":
                s = "%sif (%s) {\n%s%s}" % (pad, self.cond(), self.block(ind + 1), pad)
                if r.random() < 0.6:
                    s += " else {\n%s%s}" % (self.block(ind + 1), pad)
                return s + "\n"
            self.loop_depth += 1
            try:
                i = self.name("i")
                bound = r.choice(["%d" % r.randint(1, 6), "(int) (u * 7.0)",
                                  "(int) (v * 5.0) + 1"] +
                                 ([] if self.scope.in_function else ["n"]))
                if k == "for":
                    self.scope.ints.append(i)
                    body = self.block(ind + 1)
                    self.scope.ints.pop()
                    return "%sfor (int %s = 0; %s < %s; ++%s) {\n%s%s}\n" % (
                        pad, i, i, bound, i, body, pad)
                # while / do-while with a guaranteed bound
                body = self.block(ind + 1)
                if r.random() < 0.5:
                    return ("%sint %s = 0;\n%swhile (%s < %s) {\n%s    ++%s;\n%s%s}\n" %
                            (pad, i, pad, i, bound, pad, i, body, pad))
                return ("%sint %s = 0;\n%sdo {\n%s    ++%s;\n%s%s} while (%s < %s);\n" %
                        (pad, i, pad, pad, i, body, pad, i, bound))
            finally:
                self.loop_depth -= 1
        finally:
            self.depth -= 1

    # --- declarations ----------------------------------------------------------
    def function(self, index):
        r = self.r
        locals_ = ["t"]
        decls = "    float result = a * 0.5;\n    float t = b - a;\n"
        if r.random() < 0.5:
            decls += "    o = b * 0.25;\n"  # else written on some paths only
        if r.random() < 0.5:
            decls += "    Pair q;\n    q.a = a;\n    q.b = t;\n"
            locals_ += ["q.a", "q.b"]
        if r.random() < 0.5:
            decls += "    float arr[4] = { a, b, 0.5, -1.0 };\n"
            locals_ += ["arr[0]", "arr[1]", "arr[3]"]
        writable = ["result", "o"] + locals_
        saved = (self.scope, self.loop_depth, self.depth)
        self.scope = Scope(["a", "b"] + writable, writable, [], list(range(index)), True)
        self.loop_depth, self.depth = 0, 1
        body = self.block(1, r.randint(2, 4))
        self.scope, self.loop_depth, self.depth = saved
        return ("float helper%d(float a, float b, output float o)\n{\n%s%s"
                "    return result + b;\n}\n\n" % (index, decls, body))

    def param_init(self):
        """A function run by parameter defaults that may exit() per point."""
        r = self.r
        threshold, vmax = r.uniform(0.6, 1.6), r.uniform(0.2, 1.0)
        stop = "exit();" if self.param_exit else "a = -a;"
        return ("float pinit(float a)\n{\n"
                "    if (a > %.2f) {\n        if (v < %.2f)\n            %s\n"
                "        return a * 2.0;\n    }\n"
                "    return a - 1.0;\n}\n\n" % (threshold, vmax, stop))

    def shader(self, seed):
        r = self.r
        funcs = "".join(self.function(k) for k in range(HELPERS)) + self.param_init()
        writable = ["x", "y", "acc", "pr.a", "pr.b", "arr[0]", "arr[1]", "arr[3]"]
        readable = writable + ["k"] + (["kl"] if r.random() < 0.5 else [])
        self.scope = Scope(readable, writable, ["n"], list(range(HELPERS)), False)
        body = self.block(1, r.randint(2, 5))
        # The deepest helper always runs, so nested early returns always do.
        body += "    acc += %s;\n" % self.call("acc", HELPERS - 1)[0]
        return ("// generated by test/difftest/generate.py, seed %d\n"
                "struct Pair { float a; float b; };\n\n%s"
                "shader gen_%d(int n = %d, float k = pinit(u + v),\n"
                "              float kl = pinit(v * 2.0) [[ int lockgeom = 0 ]],\n"
                "              output float fa = 0, output float fb = 0,\n"
                "              output float facc = 0)\n{\n"
                "    float x = u * 4.0 - 2.0;\n    float y = v * 3.0 - 1.0;\n    float acc = 0;\n"
                "    Pair pr;\n    pr.a = x * y;\n    pr.b = k;\n"
                "    float arr[4] = { x, y, 0.25, k };\n"
                "%s    facc = acc + x + y + pr.a - pr.b + arr[2];\n}\n" %
                (seed, funcs, seed, r.randint(1, 5), body))


def generate(seed, param_exit=True):
    """The shader of `seed`. Without param_exit, parameter defaults do not
    exit(): OSL runs a default where its optimizer leaves the parameter's
    first use, so where such an exit stops the shader is not defined by the
    language, and comparisons with OSL leave it out."""
    return Gen(random.Random(seed), param_exit).shader(seed)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--count", type=int, default=100)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for s in range(a.seed, a.seed + a.count):
        with open(os.path.join(a.out, "gen_%d.osl" % s), "w") as f:
            f.write(generate(s))


if __name__ == "__main__":
    main()
