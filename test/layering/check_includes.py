#!/usr/bin/env python3
"""The project's dependency rules, checked on every #include "..." line.

Layers, bottom up: OslAbi (the kernel ABI: header-only, standard headers
only) < OslStrings (pure string functions) < OslDialect < OslLanes (lane
builders) < OslFrontend, OslTransforms and OslConversion (side by side:
none includes another) < OslPipeline < OslCompiler; OslSupport (pattern
helpers) depends on MLIR only. The compiler never includes the runtime, and
the runtime (OslRuntime) reads OslAbi, never the compiler. Prints each
include that breaks a rule, with file:line, and exits 1 if there is one.
"""
import argparse
import pathlib
import re
import sys

# (directories, include prefixes they must not use)
RULES = [
    (["include/OslAbi"], ["Osl", "mlir/", "llvm/"]),
    (["include/OslStrings", "lib/Strings"], ["OslRuntime/", "OslDialect/", "OslTransforms/",
                                             "OslFrontend/", "OslCompiler/", "mlir/", "llvm/"]),
    (["include/OslDialect", "lib/Dialect"], ["OslRuntime/", "OslLanes/", "OslTransforms/",
                                             "OslFrontend/", "OslCompiler/", "OslRender/"]),
    (["include/OslLanes", "lib/Lanes"], ["OslRuntime/", "OslTransforms/", "OslFrontend/",
                                         "OslCompiler/", "OslRender/"]),
    (["include/OslSupport", "lib/Support"], ["OslAbi/", "OslStrings/", "OslDialect/",
                                             "OslLanes/", "OslTransforms/", "OslConversion/",
                                             "OslPipeline/", "OslFrontend/", "OslRuntime/",
                                             "OslCompiler/", "OslRender/"]),
    (["include/OslTransforms", "lib/Transforms"], ["OslRuntime/", "OslFrontend/",
                                                   "OslConversion/", "OslPipeline/",
                                                   "OslCompiler/", "OslRender/"]),
    (["include/OslConversion", "lib/Conversion"], ["OslRuntime/", "OslFrontend/",
                                                   "OslTransforms/", "OslPipeline/",
                                                   "OslCompiler/", "OslRender/"]),
    (["include/OslPipeline", "lib/Pipeline"], ["OslRuntime/", "OslFrontend/", "OslCompiler/",
                                               "OslRender/"]),
    (["include/OslFrontend", "lib/Frontend"], ["OslRuntime/", "OslTransforms/",
                                               "OslConversion/", "OslPipeline/",
                                               "OslCompiler/", "OslRender/"]),
    (["include/OslRuntime", "lib/Runtime"], ["OslDialect/", "OslTransforms/", "OslFrontend/",
                                             "OslCompiler/", "mlir/"]),
]
# What OslAbi may include of its own.
ALLOWED = {"include/OslAbi": ["OslAbi/"]}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--root", required=True, help="the repository's root")
    root = pathlib.Path(parser.parse_args().root)
    broken = 0
    for dirs, forbidden in RULES:
        for d in dirs:
            allowed = ALLOWED.get(d, [])
            for path in sorted((root / d).rglob("*")):
                if path.suffix not in (".h", ".cpp", ".td", ".inc"):
                    continue
                for n, line in enumerate(path.read_text().splitlines(), 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = m.group(1)
                    if any(target.startswith(a) for a in allowed):
                        continue
                    if any(target.startswith(f) for f in forbidden):
                        print(f"{path.relative_to(root)}:{n}: {d} must not include \"{target}\"")
                        broken += 1
    if broken:
        print(f"{broken} include(s) break the layering rules")
        return 1
    print("layering: every include follows the rules")
    return 0


if __name__ == "__main__":
    sys.exit(main())
