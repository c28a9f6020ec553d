// Deterministic parallel loops (DESIGN 6). Element-wise loops write disjoint outputs, so any
// schedule gives the same bits. Reductions cut [0, n) into chunks of a fixed size that does not
// depend on the thread count, sum each chunk in index order, then add the chunk sums in order:
// the result is bit-identical for 1, 2 or 64 threads.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace reel {

// Below this many elements a loop runs on the calling thread: a parallel region costs microseconds.
inline constexpr std::ptrdiff_t kParallelMin = 2048;
// The threshold in force: kParallelMin, or what setParallelMin set (the determinism tests lower it
// to 1 so that their 2-thread runs go through every parallel path; `REEL_PARALLEL_MIN` does the
// same for the reel binary). Results never depend on it: only which loops open a region.
std::ptrdiff_t parallelMin();
void setParallelMin(std::ptrdiff_t n);

// One decision for all the loops of a body's step: with `work` (the body's nodes) at least a
// quarter of the threshold, every loop of kScopeMin elements or more runs in parallel; below it, none does (on
// this thread, until the scope ends; work < 0: no decision, the threshold as it is). A step whose
// loops are split between the two lets the waiting threads fall asleep in the serial ones and
// pays a wake-up in each parallel one: a 2,000-node sheet, its node loops under the threshold
// and its spring loops over it, ran 1.2x slower on two threads than on one, and 1.4x faster with
// all of them parallel (docs/engine.md, "Threads").
inline constexpr std::ptrdiff_t kScopeMin = 256;
class ParallelScope {
 public:
  explicit ParallelScope(std::ptrdiff_t work);
  ~ParallelScope();
  ParallelScope(const ParallelScope&) = delete;
  ParallelScope& operator=(const ParallelScope&) = delete;

 private:
  std::ptrdiff_t saved_;
};
// Reduction chunk size: fixed, independent of the thread count.
inline constexpr std::ptrdiff_t kReduceChunk = 1024;

template <class F>
void parallelFor(std::ptrdiff_t n, F&& body) {
#pragma omp parallel for schedule(static) if (n >= parallelMin())
  for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
}

// body(i0, i1) over [0, n) cut into blocks of `block` elements, in parallel once n reaches
// parallelMin() (the threshold is on the elements, not the blocks): for kernels that take a range
// (one call per block, not per element).
// `work`: the elements the threshold is taken on when n counts groups of them (cells of agents).
template <class F>
void parallelBlocks(std::ptrdiff_t n, std::ptrdiff_t block, F&& body, std::ptrdiff_t work = -1) {
  const std::ptrdiff_t blocks = (n + block - 1) / block;
#pragma omp parallel for schedule(static) if ((work < 0 ? n : work) >= parallelMin())
  for (std::ptrdiff_t b = 0; b < blocks; ++b) body(b * block, (b + 1) * block < n ? (b + 1) * block : n);
}

// K sums at once: term(i) returns std::array<double, K>, each component summed in a fixed order
// of operations (chunk by chunk, then the chunk sums in order). Lets a loop that updates vectors
// also return their dot products in one pass (one parallel region instead of several).
template <std::size_t K, class F>
std::array<double, K> deterministicSums(std::ptrdiff_t n, F&& term) {
  const std::ptrdiff_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
  auto chunkSum = [&](std::ptrdiff_t c) {
    const std::ptrdiff_t end = (c + 1) * kReduceChunk < n ? (c + 1) * kReduceChunk : n;
    std::array<double, K> s{};
    for (std::ptrdiff_t i = c * kReduceChunk; i < end; ++i) {
      const std::array<double, K> t = term(i);
      for (std::size_t k = 0; k < K; ++k) s[k] += t[k];
    }
    return s;
  };
  if (chunks <= 1) return chunkSum(0);  // (one chunk: no scratch, no threads)
  std::vector<std::array<double, K>> partial(static_cast<std::size_t>(chunks));
#pragma omp parallel for schedule(static) if (n >= parallelMin())
  for (std::ptrdiff_t c = 0; c < chunks; ++c) partial[static_cast<std::size_t>(c)] = chunkSum(c);
  std::array<double, K> s{};
  for (const auto& q : partial)
    for (std::size_t k = 0; k < K; ++k) s[k] += q[k];
  return s;
}

// Sum of term(i) for i in [0, n) in a fixed order of operations.
template <class F>
double deterministicSum(std::ptrdiff_t n, F&& term) {
  return deterministicSums<1>(n, [&](std::ptrdiff_t i) { return std::array<double, 1>{term(i)}; })[0];
}

// Largest of value(i) ≥ 0 for i in [0, n) (0 when n = 0): chunk maxima in parallel, then in
// order. A maximum is exact, so any thread count gives the same bits.
template <class F>
double deterministicMax(std::ptrdiff_t n, F&& value) {
  const std::ptrdiff_t chunks = (n + kReduceChunk - 1) / kReduceChunk;
  std::vector<double> part(static_cast<std::size_t>(chunks > 0 ? chunks : 1), 0.0);
#pragma omp parallel for schedule(static) if (n >= parallelMin())
  for (std::ptrdiff_t c = 0; c < chunks; ++c) {
    const std::ptrdiff_t end = (c + 1) * kReduceChunk < n ? (c + 1) * kReduceChunk : n;
    double m = 0.0;
    for (std::ptrdiff_t i = c * kReduceChunk; i < end; ++i) {
      const double v = value(i);
      if (v > m) m = v;  // NaN never wins
    }
    part[static_cast<std::size_t>(c)] = m;
  }
  double m = 0.0;
  for (double v : part) m = v > m ? v : m;
  return m;
}

// Threads used by parallel loops (what OpenMP will use); set once by the app.
int threadCount();
void setThreadCount(int n);

}  // namespace reel
