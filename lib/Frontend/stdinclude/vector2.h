// osl-mlir's vector2.h: a 2D vector, as OSL's standard header declares it,
// with component-wise arithmetic and the geometric functions.
#pragma once
#define VECTOR2_H

#include "osl-mlir-structmath.h"

struct vector2 {
    float x;
    float y;
};

OSLMLIR_STRUCT2(vector2, x, y)

float dot(vector2 a, vector2 b) { return a.x * b.x + a.y * b.y; }
float length(vector2 v) { return hypot(v.x, v.y); }
float distance(vector2 a, vector2 b) { return length(b - a); }
vector2 normalize(vector2 v)
{
    // A zero vector stays zero: division by 0 gives 0 in OSL.
    return v / length(v);
}
// Floored modulo, component by component.
vector2 mod(vector2 a, vector2 b) { return a - b * floor(a / b); }
