// The thread shares (common/threads.h).
#include <gtest/gtest.h>

#include <thread>

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

}  // namespace
}  // namespace dtm
