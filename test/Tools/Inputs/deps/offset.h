// Included by scale.h (test/Tools/make-dependencies.osl).
#define OFFSET 0.5
