// osl-mlir's color2.h: a two-channel color (a value and its alpha), as
// OSL's standard header declares it, with component-wise arithmetic.
#pragma once
#define COLOR2_H

#include "osl-mlir-structmath.h"

struct color2 {
    float r;
    float a;
};

OSLMLIR_STRUCT2(color2, r, a)
