// SPDX-License-Identifier: Apache-2.0
#include "rbf/parallel_blocks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace rbfmuscle {
namespace {

/// Per-index values and per-block sums combined in block order, as the pipeline's loops use them.
struct Result {
  std::vector<double> values;
  std::vector<long> visits;
  double sum = 0.0;
};

Result runBlocks(long count, long block_size) {
  Result r;
  r.values.assign(static_cast<size_t>(count), 0.0);
  r.visits.assign(static_cast<size_t>(count), 0);
  std::vector<double> block_sums(static_cast<size_t>((count + block_size - 1) / block_size), 0.0);
  forEachBlock(count, block_size, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) {
      r.values[static_cast<size_t>(i)] = std::sin(0.1 * static_cast<double>(i));
      ++r.visits[static_cast<size_t>(i)];
      block_sums[static_cast<size_t>(begin / block_size)] += 1e-3 * r.values[static_cast<size_t>(i)];
    }
  });
  for (double s : block_sums) r.sum += s;
  return r;
}

TEST(ParallelBlocks, VisitsEveryIndexOnceInOrderOutsideAParallelRegion) {
  std::vector<long> begins;
  forEachBlock(10, 4, [&](long begin, long end) {
    begins.push_back(begin);
    EXPECT_EQ(end, std::min(10L, begin + 4));
  });
  EXPECT_EQ(begins, (std::vector<long>{0, 4, 8}));
  const Result r = runBlocks(1001, 64);
  for (long v : r.visits) EXPECT_EQ(v, 1);
}

TEST(ParallelBlocks, TasksOfATeamGiveTheSameResultsAsOneThread) {
  const Result serial = runBlocks(5003, 37);
  for (int threads : {1, 2, 4}) {
    Result shared;
#pragma omp parallel num_threads(threads)
#pragma omp single
    {
#pragma omp task shared(shared)
      shared = runBlocks(5003, 37);
    }
    for (long v : shared.visits) ASSERT_EQ(v, 1) << threads << " threads";
    EXPECT_EQ(shared.values, serial.values) << threads << " threads";
    EXPECT_EQ(shared.sum, serial.sum) << threads << " threads";  // bitwise: same blocks, same order
  }
}

TEST(ParallelBlocks, RethrowsTheErrorOfTheFirstBlockThatThrows) {
  for (int threads : {1, 2}) {
    std::string message;
#pragma omp parallel num_threads(threads)
#pragma omp single
    try {
      forEachBlock(10, 1, [&](long begin, long) {
        if (begin == 3 || begin == 7) throw std::runtime_error("block " + std::to_string(begin));
      });
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    EXPECT_EQ(message, "block 3") << threads << " threads";
  }
}

TEST(ParallelBlocks, RefusesABlockSizeBelowOne) {
  EXPECT_THROW(forEachBlock(10, 0, [](long, long) {}), std::invalid_argument);
  EXPECT_NO_THROW(forEachBlock(0, 4, [](long, long) { FAIL() << "no block for no index"; }));
}

}  // namespace
}  // namespace rbfmuscle
