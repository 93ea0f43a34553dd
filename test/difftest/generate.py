#!/usr/bin/env python3
"""Random OSL shaders for the differential tester (osl-difftest).

  generate.py --seed S --count N --out DIR

Writes DIR/gen_<seed>.osl for seeds S .. S+N-1. Each shader is valid OSL
with divergent control flow: nested if/else on per-point conditions,
for/while/do-while loops whose trip counts differ per point (all bounded),
break and continue under varying conditions, user functions that return
early (also from inside loops) and write output parameters, exit() under a
varying condition, outputs written on some paths only, uniform loops with
varying bodies, and library calls (math, noise, geometry). The same seed
always gives the same shader.
"""
import argparse
import os
import random

FLOAT_UNARY = ["sin", "cos", "sqrt", "abs", "floor", "exp", "log", "atan", "fabs",
               "ceil", "sign", "tanh", "inversesqrt", "cbrt", "erf"]
FLOAT_BINARY = ["min", "max", "pow", "fmod", "atan2", "step", "mod"]
NOISES = ["perlin", "uperlin", "cell", "simplex", "usimplex", "hash"]


class Gen:
    def __init__(self, rng):
        self.r = rng
        self.depth = 0
        self.loop_depth = 0
        self.in_function = False
        self.counter = 0
        self.floats = ["x", "y", "acc"]
        self.ints = ["n"]

    def name(self, prefix):
        self.counter += 1
        return "%s%d" % (prefix, self.counter)

    # --- expressions ---------------------------------------------------------
    def fexpr(self, d=0):
        r = self.r
        choice = r.random()
        if d > 1 or choice < 0.3:
            return r.choice(self.floats + ["u", "v", "%.3f" % r.uniform(-2, 2)])
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
        if not self.ints:
            return "%.3f" % r.uniform(-2, 2)
        return "(float) %s" % r.choice(self.ints)

    def cond(self):
        r = self.r
        a, b = self.fexpr(1), self.fexpr(1)
        c = "%s %s %s" % (a, r.choice(["<", ">", "<=", ">="]), b)
        if r.random() < 0.2:
            c = "(%s) %s (%s %s %.2f)" % (c, r.choice(["&&", "||"]), r.choice(["u", "v"]),
                                         r.choice(["<", ">"]), r.uniform(0, 1))
        return c

    # --- statements ------------------------------------------------------------
    def block(self, indent, count=None):
        count = count if count is not None else self.r.randint(1, 3)
        return "".join(self.stmt(indent) for _ in range(count))

    def stmt(self, ind):
        r = self.r
        pad = "    " * ind
        kinds = ["assign", "assign", "assign", "out"]
        if self.depth < 3:
            kinds += ["if", "if", "for", "while"] + ([] if self.in_function else ["call"])
        if self.loop_depth > 0:
            kinds += ["break", "continue"]
        if self.in_function:
            kinds += ["return"]
        elif self.depth > 0:
            kinds += ["exit"]
        k = r.choice(kinds)
        if k == "assign":
            return "%s%s %s %s;\n" % (pad, r.choice(self.floats), r.choice(["=", "+=", "*=", "-="]),
                                     self.fexpr())
        if k == "out":
            if self.in_function:
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
            return "%sacc += helper%d(%s, %s);\n" % (pad, r.randint(0, 1), self.fexpr(1),
                                                   self.fexpr(1))
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
                                  "(int) (v * 5.0) + 1"] + ([] if self.in_function else ["n"]))
                if k == "for":
                    self.ints.append(i)
                    body = self.block(ind + 1)
                    self.ints.pop()
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

    def function(self, index):
        saved = (self.floats, self.ints, self.in_function, self.loop_depth, self.depth)
        self.floats, self.ints, self.in_function, self.loop_depth, self.depth = (
            ["a", "b", "result"], [], True, 0, 1)
        body = self.block(1, self.r.randint(2, 4))
        self.floats, self.ints, self.in_function, self.loop_depth, self.depth = saved
        return ("float helper%d(float a, float b)\n{\n    float result = a * 0.5;\n%s"
                "    return result + b;\n}\n\n" % (index, body))

    def shader(self, seed):
        funcs = self.function(0) + self.function(1)
        body = self.block(1, self.r.randint(2, 5))
        return ("// generated by test/difftest/generate.py, seed %d\n%s"
                "shader gen_%d(int n = %d, output float fa = 0, output float fb = -1,\n"
                "              output float facc = 0)\n{\n"
                "    float x = u * 4.0 - 2.0;\n    float y = v * 3.0 - 1.0;\n    float acc = 0;\n"
                "%s    facc = acc + x + y;\n}\n" % (seed, funcs, seed, self.r.randint(1, 5), body))


def generate(seed):
    return Gen(random.Random(seed)).shader(seed)


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
