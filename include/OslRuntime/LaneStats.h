//===- LaneStats.h - How full the SIMD lanes of masked blocks are -*- C++ -*-===//
//
// A kernel compiled with lane counting (CompileOptions::countLanes) calls
// osl_rt_count_lanes at the start of every masked block it executes (an arm
// of a varying if, an iteration of a varying loop) with the number of the
// batch's shading points active in it. The totals give the mean fraction
// of active lanes per executed block: 1 when divergence costs nothing, 1/W
// when every block runs for a single lane.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_LANESTATS_H
#define OSLRUNTIME_LANESTATS_H

#include "OslAbi/EntryPoints.h"

#include <cstdint>

namespace osl {

struct LaneStats {
  uint64_t blocks = 0;      // masked blocks executed
  uint64_t activeLanes = 0; // their active lanes, summed
  /// Mean fraction of `width` lanes active per executed block (0 if none).
  double meanActiveFraction(int width) const {
    return blocks ? double(activeLanes) / (double(blocks) * width) : 0.0;
  }
};

/// The totals since the last reset.
LaneStats laneStats();
void resetLaneStats();

} // namespace osl

#endif // OSLRUNTIME_LANESTATS_H
