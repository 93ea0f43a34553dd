// osl-mlir's matrix33.h: a 3x3 matrix held in the upper-left corner of a
// 4x4 matrix (the rest as the identity), so the 4x4 library does the work.
#pragma once
#define MATRIX33_H

struct matrix33 {
    matrix m;
};

// The 3x3 part of `m`; the rest of the 4x4 becomes the identity's.
matrix33 makeMatrix33(matrix m)
{
    return matrix33(matrix(m[0][0], m[0][1], m[0][2], 0.0,
                           m[1][0], m[1][1], m[1][2], 0.0,
                           m[2][0], m[2][1], m[2][2], 0.0,
                           0.0, 0.0, 0.0, 1.0));
}

matrix33 __operator__neg__(matrix33 a) { return makeMatrix33(-a.m); }
matrix33 __operator__add__(matrix33 a, matrix33 b) { return makeMatrix33(a.m + b.m); }
matrix33 __operator__sub__(matrix33 a, matrix33 b) { return makeMatrix33(a.m - b.m); }
matrix33 __operator__mul__(matrix33 a, matrix33 b) { return matrix33(a.m * b.m); }
matrix33 __operator__mul__(matrix33 a, float b) { return makeMatrix33(a.m * b); }
matrix33 __operator__mul__(float a, matrix33 b) { return makeMatrix33(a * b.m); }
matrix33 __operator__div__(matrix33 a, matrix33 b) { return matrix33(a.m / b.m); }
matrix33 __operator__div__(matrix33 a, float b) { return makeMatrix33(a.m / b); }
int __operator__eq__(matrix33 a, matrix33 b) { return a.m == b.m; }
int __operator__ne__(matrix33 a, matrix33 b) { return a.m != b.m; }

float determinant(matrix33 a) { return determinant(a.m); }
matrix33 transpose(matrix33 a) { return matrix33(transpose(a.m)); }
point transform(matrix33 a, point p) { return transform(a.m, p); }
vector transform(matrix33 a, vector v) { return transform(a.m, v); }
normal transform(matrix33 a, normal n) { return transform(a.m, n); }
