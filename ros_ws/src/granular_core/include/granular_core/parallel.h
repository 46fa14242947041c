#pragma once

// One parallel loop for every layer: OpenMP threads, exceptions carried out of the loop.

#include <cstddef>
#include <exception>
#include <functional>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace granular {

/// Calls work(i) for every i < count on `threads` threads (0: OpenMP's default), handing out
/// `chunk` indices at a time (dynamic schedule). `progress(done, count)`, when set, is called
/// after each index, one call at a time. An exception thrown by work or progress never escapes
/// a thread (which would end the process): once every index has run, the exception of the
/// lowest index that threw is rethrown, so a failing run names the same item whatever the
/// thread count.
template <typename Work>
void parallelFor(std::size_t count, [[maybe_unused]] int threads, int chunk, Work&& work,
                 const std::function<void(std::size_t, std::size_t)>& progress = {}) {
  std::exception_ptr error;
  std::size_t error_at = count;
  std::size_t done = 0;
  const auto keep = [&](std::size_t index, std::exception_ptr thrown) {
#pragma omp critical(granular_parallel_for_error)
    if (index < error_at) {
      error_at = index;
      error = thrown;
    }
  };
  [[maybe_unused]] int team = 1;
#ifdef _OPENMP
  team = threads > 0 ? threads : omp_get_max_threads();
#endif
#pragma omp parallel for schedule(dynamic, chunk) num_threads(team)
  for (long i = 0; i < static_cast<long>(count); ++i) {
    const auto index = static_cast<std::size_t>(i);
    try {
      work(index);
    } catch (...) {
      keep(index, std::current_exception());
    }
    if (progress) {
#pragma omp critical(granular_parallel_for_progress)
      try {
        progress(++done, count);
      } catch (...) {
        keep(index, std::current_exception());
      }
    }
  }
  if (error) {
    std::rethrow_exception(error);
  }
}

/// The calling thread's number in the team of the parallelFor running it, 0 to threads - 1
/// (0 outside one): for work that keeps scratch space per thread.
inline int threadIndex() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

}  // namespace granular
