#!/usr/bin/env python3
"""Shrinks a shader on which osl-difftest fails, keeping it failing.

  reduce.py --difftest PATH [--message TEXT] IN.osl OUT.osl

Greedy delta debugging over lines: removes single lines, then lines with
the block they open ({ ... }), then replaces expressions after '=' by 0,
keeping a change whenever the shader still compiles and osl-difftest still
reports MISMATCH on it. The result goes to OUT.osl, ready to be kept under
test/difftest/regress/ as a regression test.
"""
import argparse
import os
import subprocess
import sys
import tempfile


MESSAGE = None


def fails(difftest, text):
    with tempfile.NamedTemporaryFile("w", suffix=".osl", delete=False) as f:
        f.write(text)
        path = f.name
    try:
        r = subprocess.run([difftest, "--quiet", path], capture_output=True, text=True,
                           timeout=120)
        if MESSAGE:
            return MESSAGE in r.stderr
        return r.returncode == 1 and "MISMATCH" in r.stderr
    except subprocess.TimeoutExpired:
        return False
    finally:
        os.remove(path)


def block_end(lines, i):
    """The line closing the block opened on line i (or i if none opens)."""
    depth = 0
    for j in range(i, len(lines)):
        depth += lines[j].count("{") - lines[j].count("}")
        if depth <= 0 and j > i:
            return j
        if depth <= 0 and j == i:
            return i
    return i


def reduce_lines(difftest, lines):
    changed = True
    while changed:
        changed = False
        i = 0
        while i < len(lines):
            for end in sorted({i, block_end(lines, i)}, reverse=True):
                candidate = lines[:i] + lines[end + 1:]
                if candidate and fails(difftest, "".join(candidate)):
                    lines = candidate
                    changed = True
                    break
            else:
                i += 1
    return lines


def simplify_expressions(difftest, lines):
    for i, line in enumerate(lines):
        if "=" in line and line.rstrip().endswith(";") and "==" not in line:
            head = line[:line.index("=") + 1]
            candidate = lines[:i] + [head + " 0;\n"] + lines[i + 1:]
            if fails(difftest, "".join(candidate)):
                lines = candidate
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--difftest", required=True)
    ap.add_argument("--message")
    ap.add_argument("input")
    ap.add_argument("output")
    a = ap.parse_args()
    global MESSAGE
    MESSAGE = a.message
    lines = open(a.input).readlines()
    if not fails(a.difftest, "".join(lines)):
        print("%s does not fail; nothing to reduce" % a.input)
        return 1
    lines = reduce_lines(a.difftest, lines)
    lines = simplify_expressions(a.difftest, lines)
    lines = reduce_lines(a.difftest, lines)
    open(a.output, "w").write("".join(lines))
    print("reduced %s to %d lines in %s" % (a.input, len(lines), a.output))
    return 0


if __name__ == "__main__":
    sys.exit(main())
