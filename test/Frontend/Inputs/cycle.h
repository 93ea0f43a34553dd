// Includes itself: error_in_include.osl checks the cycle is reported.
#include "cycle.h"
