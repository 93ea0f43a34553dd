// osl-mlir's own: the component-wise operators and math of the small
// struct types of color2.h, color4.h, vector2.h and vector4.h, written
// once as macros that each header instantiates for its struct.
//
// OSLMLIR_STRUCT2(T, A, B): T has two fields A and B (floats, or for
// color4 a color and a float); OSLMLIR_STRUCT4(T, A, B, C, D): four floats.
#pragma once

// --- two fields ------------------------------------------------------------
#define OSLMLIR_UNARY2(T, A, B, f) \
    T f(T v) { return T(f(v.A), f(v.B)); }
#define OSLMLIR_BINARY2(T, A, B, f) \
    T f(T a, T b) { return T(f(a.A, b.A), f(a.B, b.B)); } \
    T f(T a, float b) { return T(f(a.A, b), f(a.B, b)); }
#define OSLMLIR_OPERATOR2(T, A, B, name, op) \
    T __operator__##name##__(T a, T b) { return T(a.A op b.A, a.B op b.B); } \
    T __operator__##name##__(T a, float b) { return T(a.A op b, a.B op b); } \
    T __operator__##name##__(float a, T b) { return T(a op b.A, a op b.B); }

// Division by a float multiplies by its reciprocal, as OSL's headers do.
#define OSLMLIR_DIVIDE2(T, A, B) \
    T __operator__div__(T a, T b) { return T(a.A / b.A, a.B / b.B); } \
    T __operator__div__(T a, float b) { float r = 1.0 / b; return T(a.A * r, a.B * r); } \
    T __operator__div__(float a, T b) { return T(a / b.A, a / b.B); }

#define OSLMLIR_STRUCT2(T, A, B) \
    T __operator__neg__(T a) { return T(-a.A, -a.B); } \
    OSLMLIR_OPERATOR2(T, A, B, add, +) \
    OSLMLIR_OPERATOR2(T, A, B, sub, -) \
    OSLMLIR_OPERATOR2(T, A, B, mul, *) \
    OSLMLIR_DIVIDE2(T, A, B) \
    int __operator__eq__(T a, T b) { return a.A == b.A && a.B == b.B; } \
    int __operator__neq__(T a, T b) { return a.A != b.A || a.B != b.B; } \
    OSLMLIR_UNARY2(T, A, B, abs) OSLMLIR_UNARY2(T, A, B, ceil) \
    OSLMLIR_UNARY2(T, A, B, floor) OSLMLIR_UNARY2(T, A, B, round) \
    OSLMLIR_UNARY2(T, A, B, trunc) OSLMLIR_UNARY2(T, A, B, sign) \
    OSLMLIR_UNARY2(T, A, B, sqrt) OSLMLIR_UNARY2(T, A, B, inversesqrt) \
    OSLMLIR_UNARY2(T, A, B, exp) OSLMLIR_UNARY2(T, A, B, exp2) \
    OSLMLIR_UNARY2(T, A, B, log) OSLMLIR_UNARY2(T, A, B, log2) \
    OSLMLIR_UNARY2(T, A, B, log10) \
    OSLMLIR_UNARY2(T, A, B, sin) OSLMLIR_UNARY2(T, A, B, cos) \
    OSLMLIR_UNARY2(T, A, B, tan) OSLMLIR_UNARY2(T, A, B, asin) \
    OSLMLIR_UNARY2(T, A, B, acos) OSLMLIR_UNARY2(T, A, B, atan) \
    OSLMLIR_BINARY2(T, A, B, fmod) OSLMLIR_BINARY2(T, A, B, pow) \
    OSLMLIR_BINARY2(T, A, B, atan2) OSLMLIR_BINARY2(T, A, B, step) \
    T max(T a, T b) { return T(max(a.A, b.A), max(a.B, b.B)); } \
    T max(T a, float b) { return T(max(a.A, b), max(a.B, b)); } \
    T min(T a, T b) { return T(min(a.A, b.A), min(a.B, b.B)); } \
    T min(T a, float b) { return T(min(a.A, b), min(a.B, b)); } \
    T clamp(T x, T lo, T hi) { return T(clamp(x.A, lo.A, hi.A), clamp(x.B, lo.B, hi.B)); } \
    T clamp(T x, float lo, float hi) { return T(clamp(x.A, lo, hi), clamp(x.B, lo, hi)); } \
    T mix(T a, T b, T x) { return T(mix(a.A, b.A, x.A), mix(a.B, b.B, x.B)); } \
    T mix(T a, T b, float x) { return T(mix(a.A, b.A, x), mix(a.B, b.B, x)); } \
    T smoothstep(T e0, T e1, T x) \
    { return T(smoothstep(e0.A, e1.A, x.A), smoothstep(e0.B, e1.B, x.B)); } \
    T smoothstep(float e0, float e1, T x) \
    { return T(smoothstep(e0, e1, x.A), smoothstep(e0, e1, x.B)); }

// --- four float fields -------------------------------------------------------
#define OSLMLIR_UNARY4(T, A, B, C, D, f) \
    T f(T v) { return T(f(v.A), f(v.B), f(v.C), f(v.D)); }
#define OSLMLIR_BINARY4(T, A, B, C, D, f) \
    T f(T a, T b) { return T(f(a.A, b.A), f(a.B, b.B), f(a.C, b.C), f(a.D, b.D)); } \
    T f(T a, float b) { return T(f(a.A, b), f(a.B, b), f(a.C, b), f(a.D, b)); }
#define OSLMLIR_OPERATOR4(T, A, B, C, D, name, op) \
    T __operator__##name##__(T a, T b) \
    { return T(a.A op b.A, a.B op b.B, a.C op b.C, a.D op b.D); } \
    T __operator__##name##__(T a, float b) \
    { return T(a.A op b, a.B op b, a.C op b, a.D op b); } \
    T __operator__##name##__(float a, T b) \
    { return T(a op b.A, a op b.B, a op b.C, a op b.D); }

#define OSLMLIR_DIVIDE4(T, A, B, C, D) \
    T __operator__div__(T a, T b) { return T(a.A / b.A, a.B / b.B, a.C / b.C, a.D / b.D); } \
    T __operator__div__(T a, float b) \
    { float r = 1.0 / b; return T(a.A * r, a.B * r, a.C * r, a.D * r); } \
    T __operator__div__(float a, T b) { return T(a / b.A, a / b.B, a / b.C, a / b.D); }

#define OSLMLIR_STRUCT4(T, A, B, C, D) \
    T __operator__neg__(T a) { return T(-a.A, -a.B, -a.C, -a.D); } \
    OSLMLIR_OPERATOR4(T, A, B, C, D, add, +) \
    OSLMLIR_OPERATOR4(T, A, B, C, D, sub, -) \
    OSLMLIR_OPERATOR4(T, A, B, C, D, mul, *) \
    OSLMLIR_DIVIDE4(T, A, B, C, D) \
    int __operator__eq__(T a, T b) \
    { return a.A == b.A && a.B == b.B && a.C == b.C && a.D == b.D; } \
    int __operator__neq__(T a, T b) { return !(a == b); } \
    OSLMLIR_UNARY4(T, A, B, C, D, abs) OSLMLIR_UNARY4(T, A, B, C, D, ceil) \
    OSLMLIR_UNARY4(T, A, B, C, D, floor) OSLMLIR_UNARY4(T, A, B, C, D, round) \
    OSLMLIR_UNARY4(T, A, B, C, D, trunc) OSLMLIR_UNARY4(T, A, B, C, D, sign) \
    OSLMLIR_UNARY4(T, A, B, C, D, sqrt) OSLMLIR_UNARY4(T, A, B, C, D, inversesqrt) \
    OSLMLIR_UNARY4(T, A, B, C, D, exp) OSLMLIR_UNARY4(T, A, B, C, D, exp2) \
    OSLMLIR_UNARY4(T, A, B, C, D, log) OSLMLIR_UNARY4(T, A, B, C, D, log2) \
    OSLMLIR_UNARY4(T, A, B, C, D, log10) \
    OSLMLIR_UNARY4(T, A, B, C, D, sin) OSLMLIR_UNARY4(T, A, B, C, D, cos) \
    OSLMLIR_UNARY4(T, A, B, C, D, tan) OSLMLIR_UNARY4(T, A, B, C, D, asin) \
    OSLMLIR_UNARY4(T, A, B, C, D, acos) OSLMLIR_UNARY4(T, A, B, C, D, atan) \
    OSLMLIR_BINARY4(T, A, B, C, D, fmod) OSLMLIR_BINARY4(T, A, B, C, D, pow) \
    OSLMLIR_BINARY4(T, A, B, C, D, atan2) OSLMLIR_BINARY4(T, A, B, C, D, step) \
    T max(T a, T b) { return T(max(a.A, b.A), max(a.B, b.B), max(a.C, b.C), max(a.D, b.D)); } \
    T max(T a, float b) { return T(max(a.A, b), max(a.B, b), max(a.C, b), max(a.D, b)); } \
    T min(T a, T b) { return T(min(a.A, b.A), min(a.B, b.B), min(a.C, b.C), min(a.D, b.D)); } \
    T min(T a, float b) { return T(min(a.A, b), min(a.B, b), min(a.C, b), min(a.D, b)); } \
    T clamp(T x, T lo, T hi) \
    { return T(clamp(x.A, lo.A, hi.A), clamp(x.B, lo.B, hi.B), \
               clamp(x.C, lo.C, hi.C), clamp(x.D, lo.D, hi.D)); } \
    T clamp(T x, float lo, float hi) \
    { return T(clamp(x.A, lo, hi), clamp(x.B, lo, hi), clamp(x.C, lo, hi), clamp(x.D, lo, hi)); } \
    T mix(T a, T b, T x) \
    { return T(mix(a.A, b.A, x.A), mix(a.B, b.B, x.B), mix(a.C, b.C, x.C), mix(a.D, b.D, x.D)); } \
    T mix(T a, T b, float x) \
    { return T(mix(a.A, b.A, x), mix(a.B, b.B, x), mix(a.C, b.C, x), mix(a.D, b.D, x)); } \
    T smoothstep(T e0, T e1, T x) \
    { return T(smoothstep(e0.A, e1.A, x.A), smoothstep(e0.B, e1.B, x.B), \
               smoothstep(e0.C, e1.C, x.C), smoothstep(e0.D, e1.D, x.D)); } \
    T smoothstep(float e0, float e1, T x) \
    { return T(smoothstep(e0, e1, x.A), smoothstep(e0, e1, x.B), \
               smoothstep(e0, e1, x.C), smoothstep(e0, e1, x.D)); }
