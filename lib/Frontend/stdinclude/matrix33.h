// osl-mlir's matrix33.h: a 3x3 matrix held in a 4x4 matrix, as OSL's
// standard header declares it. Its operators apply to the whole 4x4, as
// OSL's do (2 * m scales m[3][3] too, which transform() then divides by).
#pragma once
#define MATRIX33_H

struct matrix33 {
    matrix m;
};

// Whether `m` holds no translation or projection (a 3x3 in a 4x4).
int isValidAs33(matrix m)
{
    return m[0][3] == 0 && m[1][3] == 0 && m[2][3] == 0 && m[3][0] == 0 && m[3][1] == 0 &&
           m[3][2] == 0 && m[3][3] == 1;
}

matrix matrix33To44(matrix33 a) { return a.m; }

// The 3x3 part of `m`, the rest of the 4x4 the identity's.
matrix33 matrix44To33(matrix m)
{
    return matrix33(matrix(m[0][0], m[0][1], m[0][2], 0.0,
                           m[1][0], m[1][1], m[1][2], 0.0,
                           m[2][0], m[2][1], m[2][2], 0.0,
                           0.0, 0.0, 0.0, 1.0));
}
// osl-mlir's earlier name for matrix44To33.
matrix33 makeMatrix33(matrix m) { return matrix44To33(m); }

matrix33 __operator__neg__(matrix33 a) { return matrix33(-a.m); }
matrix33 __operator__add__(matrix33 a, matrix33 b) { return matrix33(a.m + b.m); }
matrix33 __operator__sub__(matrix33 a, matrix33 b) { return matrix33(a.m - b.m); }
matrix33 __operator__mul__(matrix33 a, matrix33 b) { return matrix33(a.m * b.m); }
matrix33 __operator__mul__(matrix33 a, float b) { return matrix33(a.m * b); }
matrix33 __operator__mul__(float a, matrix33 b) { return matrix33(a * b.m); }
matrix33 __operator__div__(matrix33 a, matrix33 b) { return matrix33(a.m / b.m); }
matrix33 __operator__div__(matrix33 a, float b) { return matrix33(a.m / b); }
matrix33 __operator__div__(float a, matrix33 b) { return matrix33(a / b.m); }
int __operator__eq__(matrix33 a, matrix33 b) { return a.m == b.m; }
int __operator__ne__(matrix33 a, matrix33 b) { return a.m != b.m; }

float determinant(matrix33 a) { return determinant(a.m); }
matrix33 transpose(matrix33 a) { return matrix33(transpose(a.m)); }
point transform(matrix33 a, point p) { return transform(a.m, p); }
vector transform(matrix33 a, vector v) { return transform(a.m, v); }
normal transform(matrix33 a, normal n) { return transform(a.m, n); }
