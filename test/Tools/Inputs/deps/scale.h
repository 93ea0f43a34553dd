// Included by test/Tools/make-dependencies.osl.
#include "offset.h"
#define SCALE 2.0
