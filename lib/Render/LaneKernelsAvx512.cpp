//===- LaneKernelsAvx512.cpp - The renderer's loops for AVX-512 -----------===//
#define OSL_LANE_TARGET __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,avx2")))
#define OSL_LANE_KERNELS avx512LaneKernels
#define OSL_LANE_ISA_NAME "avx512"
#include "LaneKernelsImpl.h"
