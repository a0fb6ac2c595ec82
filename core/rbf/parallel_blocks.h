// SPDX-License-Identifier: Apache-2.0
#pragma once
/// @file
/// Per-point loops of a muscle's frame, shared among the threads that the frame's muscles
/// leave idle.
#include <functional>

namespace rbfmuscle {

/// Runs body(begin, end) over [0, count) in blocks of block_size (> 0) indices. The blocks
/// depend on count and block_size alone, so a body that writes per index (or per block,
/// combined afterwards in block order) gives the same result on any number of threads.
/// Inside an active OpenMP parallel region (a frame's muscles run as its tasks, see
/// Session::step) the blocks are tasks that any idle thread of the team takes; otherwise
/// they run in order on the calling thread. The exception of the first block that throws
/// (in block order) is rethrown; whether later blocks ran is unspecified.
void forEachBlock(long count, long block_size, const std::function<void(long begin, long end)>& body);

}  // namespace rbfmuscle
