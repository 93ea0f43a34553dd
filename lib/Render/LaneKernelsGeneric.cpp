//===- LaneKernelsGeneric.cpp - The renderer's loops for plain x86-64 -----===//
#define OSL_LANE_TARGET 
#define OSL_LANE_KERNELS genericLaneKernels
#define OSL_LANE_ISA_NAME "generic"
#include "LaneKernelsImpl.h"
