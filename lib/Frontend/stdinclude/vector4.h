// osl-mlir's vector4.h: a 4D vector, as OSL's standard header declares
// it, with component-wise arithmetic and the geometric functions.
#pragma once
#define VECTOR4_H

#include "osl-mlir-structmath.h"

struct vector4 {
    float x;
    float y;
    float z;
    float w;
};

OSLMLIR_STRUCT4(vector4, x, y, z, w)

float dot(vector4 a, vector4 b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
float length(vector4 v) { return sqrt(dot(v, v)); }
float distance(vector4 a, vector4 b) { return length(b - a); }
vector4 normalize(vector4 v)
{
    // A zero vector stays zero: division by 0 gives 0 in OSL.
    return v / length(v);
}
// The 3D point a homogeneous vector4 stands for.
vector vec4ToVec3(vector4 v) { return vector(v.x, v.y, v.z) / v.w; }
// M times p as a row vector, w included (no divide).
vector4 transform(matrix M, vector4 p)
{
    return vector4(M[0][0] * p.x + M[1][0] * p.y + M[2][0] * p.z + M[3][0] * p.w,
                   M[0][1] * p.x + M[1][1] * p.y + M[2][1] * p.z + M[3][1] * p.w,
                   M[0][2] * p.x + M[1][2] * p.y + M[2][2] * p.z + M[3][2] * p.w,
                   M[0][3] * p.x + M[1][3] * p.y + M[2][3] * p.z + M[3][3] * p.w);
}
vector4 transform(string fromspace, string tospace, vector4 p)
{
    return transform(matrix(fromspace, tospace), p);
}
