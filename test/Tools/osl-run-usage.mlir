// osl-run's command line: usage, bad flags and missing files are clear
// errors with a non-zero exit, never a crash.
// RUN: osl-run | FileCheck %s --check-prefix=USAGE
// RUN: not osl-run %shaders/marble.osl --width 3 2>&1 | FileCheck %s --check-prefix=WIDTH
// RUN: not osl-run %shaders/marble.osl --math=bogus 2>&1 | FileCheck %s --check-prefix=MATH
// RUN: not osl-run %shaders/marble.osl --math 2>&1 | FileCheck %s --check-prefix=MATHARG
// RUN: not osl-run %shaders/marble.osl --frobnicate 2>&1 | FileCheck %s --check-prefix=FLAG
// RUN: not osl-run %shaders/marble.osl --userdata:type=colr c 1 2>&1 | FileCheck %s --check-prefix=UDTYPE
// RUN: not osl-run %shaders/marble.osl --userdata:type=color c 1,x 2>&1 | FileCheck %s --check-prefix=UDVALUE
// RUN: not osl-run %t.does-not-exist.osl 2>&1 | FileCheck %s --check-prefix=MISSING
// RUN: not osl-run %shaders/marble.osl -g 8 8 -o nosuch %t.png 2>&1 | FileCheck %s --check-prefix=OUTPUT
// RUN: osl-run %shaders/marble.osl -g 8 8 -o Cout %t.exr --stats --no-cache 2>&1 | FileCheck %s --check-prefix=STATS
// USAGE: usage: osl-run SHADER.osl [options]
// WIDTH: osl-run: error: --width must be 1, 4, 8 or 16
// MATH: osl-run: error: --math must be fast, default, precise or double (got 'bogus')
// MATHARG: osl-run: error: --math needs 1 argument
// FLAG: osl-run: error: unknown option '--frobnicate' (osl-run --help lists the options)
// FLAG-NOT: usage
// UDTYPE: osl-run: error: --userdata: unknown type 'colr'
// UDVALUE: osl-run: error: --userdata: '1,x' is not one or three numbers for type color
// MISSING: osl-run: error: cannot read '{{.*}}does-not-exist.osl'
// OUTPUT: error: shader 'marble' has no output 'nosuch'; outputs: Cout
// STATS: front end
// STATS: mlir passes
// STATS: llvm opt
// STATS: shading
// STATS: ns per point
