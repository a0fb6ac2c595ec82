// SPDX-License-Identifier: Apache-2.0
#include "rbf/parallel_blocks.h"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace rbfmuscle {

void forEachBlock(long count, long block_size, const std::function<void(long begin, long end)>& body) {
  if (!(block_size > 0)) throw std::invalid_argument("forEachBlock: block_size must be > 0");
  if (count <= 0) return;
  const long blocks = (count + block_size - 1) / block_size;
  bool shared = blocks > 1;
#ifdef _OPENMP
  shared = shared && omp_in_parallel();
#else
  shared = false;
#endif
  if (!shared) {
    for (long b = 0; b < blocks; ++b) body(b * block_size, std::min(count, (b + 1) * block_size));
    return;
  }
  // An exception must not leave a task: each block keeps its own, the first is rethrown.
  std::vector<std::exception_ptr> errors(static_cast<size_t>(blocks));
#pragma omp taskloop grainsize(1) shared(errors, body)
  for (long b = 0; b < blocks; ++b) {
    try {
      body(b * block_size, std::min(count, (b + 1) * block_size));
    } catch (...) {
      errors[static_cast<size_t>(b)] = std::current_exception();
    }
  }
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace rbfmuscle
