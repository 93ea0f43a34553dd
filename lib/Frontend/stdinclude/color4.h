// osl-mlir's color4.h: an RGB color with alpha, as OSL's standard header
// declares it, with component-wise arithmetic.
#pragma once
#define COLOR4_H

#include "osl-mlir-structmath.h"

struct color4 {
    color rgb;
    float a;
};

OSLMLIR_STRUCT2(color4, rgb, a)

// The color converted between spaces; alpha unchanged.
color4 transformc(string fromspace, string tospace, color4 c)
{
    return color4(transformc(fromspace, tospace, c.rgb), c.a);
}
