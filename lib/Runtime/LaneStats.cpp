//===- LaneStats.cpp - How full the SIMD lanes of masked blocks are -------===//
#include "OslRuntime/LaneStats.h"

#include <atomic>

namespace {
// Relaxed atomics: only the totals matter, read after shading has joined.
std::atomic<uint64_t> blocks{0};
std::atomic<uint64_t> activeLanes{0};
} // namespace

extern "C" void osl_rt_count_lanes(int32_t active) {
  blocks.fetch_add(1, std::memory_order_relaxed);
  activeLanes.fetch_add(uint64_t(active), std::memory_order_relaxed);
}

osl::LaneStats osl::laneStats() {
  return {blocks.load(std::memory_order_relaxed), activeLanes.load(std::memory_order_relaxed)};
}

void osl::resetLaneStats() {
  blocks.store(0, std::memory_order_relaxed);
  activeLanes.store(0, std::memory_order_relaxed);
}
