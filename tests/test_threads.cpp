// The thread shares (common/threads.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <thread>
#include <utility>
#include <vector>

#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/threads.h"

namespace dtm {
namespace {

// A share holds for the thread that made it, while it lives.
TEST(ThreadShare, HoldsForItsThreadWhileItLives) {
  const int before = thread_count();
  {
    const ThreadShare share(3);
    EXPECT_EQ(thread_count(), 3);
    int other = 0;
    std::thread([&] { other = thread_count(); }).join();
    EXPECT_EQ(other, before);
    {
      const ThreadShare inner(1);
      EXPECT_EQ(thread_count(), 1);
    }
    EXPECT_EQ(thread_count(), 3);
  }
  EXPECT_EQ(thread_count(), before);
}

TEST(ParallelHelpers, CollectInOrderIsWhatALoopAppends) {
  for (size_t n : {size_t{0}, size_t{1}, size_t{5}, size_t{100000}})
    for (size_t block : {size_t{1}, size_t{7}, size_t{4096}}) {
      std::vector<size_t> want;
      for (size_t i = 0; i < n; ++i)
        if (i % 3 != 1) want.push_back(i * i);
      const auto got = collect_in_order<size_t>(n, block, [](size_t first, size_t last, auto& out) {
        for (size_t i = first; i < last; ++i)
          if (i % 3 != 1) out.push_back(i * i);
      });
      EXPECT_EQ(got, want) << n << " by " << block;
    }
}

TEST(ParallelHelpers, ParallelSortIsStdSort) {
  std::vector<std::pair<uint32_t, uint32_t>> items;
  uint64_t x = 12345;
  for (uint32_t i = 0; i < 200000; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    items.emplace_back(static_cast<uint32_t>(x >> 40) % 1000, i);
  }
  auto want = items;
  std::sort(want.begin(), want.end());
  parallel_sort(items.begin(), items.end());
  EXPECT_EQ(items, want);
}

}  // namespace
}  // namespace dtm
