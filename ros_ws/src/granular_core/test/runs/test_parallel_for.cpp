// The parallel loop every layer uses: every index once, the lowest failing index's exception.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/parallel.h"

namespace granular {
namespace {

TEST(ParallelFor, RunsEveryIndexOnceOnAnyThreadCount) {
  for (const int threads : {1, 2, 4, 0}) {
    std::vector<std::atomic<int>> runs(1000);
    parallelFor(runs.size(), threads, 3, [&](std::size_t i) { ++runs[i]; });
    for (std::size_t i = 0; i < runs.size(); ++i) {
      ASSERT_EQ(runs[i], 1) << "index " << i << " on " << threads << " threads";
    }
  }
}

TEST(ParallelFor, RethrowsTheLowestFailingIndexAfterEveryIndexRan) {
  for (const int threads : {1, 2, 4}) {
    std::vector<std::atomic<int>> runs(1000);
    try {
      // Index 2 is slow to fail: on more than one thread, index 600 fails first.
      parallelFor(runs.size(), threads, 1, [&](std::size_t i) {
        ++runs[i];
        if (i == 2) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        if (i == 2 || i == 600) {
          throw std::runtime_error("object " + std::to_string(i));
        }
      });
      FAIL() << "no exception on " << threads << " threads";
    } catch (const std::runtime_error& error) {
      EXPECT_STREQ(error.what(), "object 2") << threads << " threads";
    }
    for (std::size_t i = 0; i < runs.size(); ++i) {
      ASSERT_EQ(runs[i], 1) << "index " << i << " on " << threads << " threads";
    }
  }
}

TEST(ParallelFor, ReportsProgressOncePerIndexInOrder) {
  std::vector<std::size_t> done;
  parallelFor(
      50, 4, 2, [](std::size_t) {},
      [&](std::size_t finished, std::size_t count) {
        EXPECT_EQ(count, 50u);
        done.push_back(finished);
      });
  ASSERT_EQ(done.size(), 50u);
  for (std::size_t i = 0; i < done.size(); ++i) {
    EXPECT_EQ(done[i], i + 1);
  }
}

TEST(ParallelFor, AProgressThatThrowsEndsTheLoopNotTheProcess) {
  std::vector<std::atomic<int>> runs(100);
  EXPECT_THROW(parallelFor(
                   runs.size(), 4, 1, [&](std::size_t i) { ++runs[i]; },
                   [](std::size_t done, std::size_t) {
                     if (done == 50) {
                       throw std::runtime_error("the terminal went away");
                     }
                   }),
               std::runtime_error);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    ASSERT_EQ(runs[i], 1) << "index " << i;
  }
}

TEST(ParallelFor, NothingToDoCallsNothing) {
  bool called = false;
  parallelFor(0, 2, 1, [&](std::size_t) { called = true; },
              [&](std::size_t, std::size_t) { called = true; });
  EXPECT_FALSE(called);
}

}  // namespace
}  // namespace granular
