//===- LaneKernelsAvx2.cpp - The renderer's loops for AVX2 ----------------===//
#define OSL_LANE_TARGET __attribute__((target("avx2")))
#define OSL_LANE_KERNELS avx2LaneKernels
#define OSL_LANE_ISA_NAME "avx2"
#include "LaneKernelsImpl.h"
