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
