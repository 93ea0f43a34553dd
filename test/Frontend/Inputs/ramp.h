// A header for include.osl: a macro and a function.
#define RAMP_SCALE 2.0
float ramp(float x) { return clamp(x * RAMP_SCALE, 0.0, 1.0); }
