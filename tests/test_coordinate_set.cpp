// CoordinateSet against a std::set: counts, ranks and selections of present
// and absent values in any interval, for grids from 2 to 2^24 values (one
// partial block up to 4096 blocks).
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "bitstream/coordinate_set.h"

namespace dtm {
namespace {

TEST(CoordinateSet, AgreesWithAnOrderedSet) {
  for (int q : {1, 3, 6, 7, 10, 12, 13, 20, 24}) {
    const uint64_t size = uint64_t{1} << q;
    std::mt19937 rng(q);
    CoordinateSet set(q);
    std::set<uint32_t> reference;
    for (int round = 0; round < 300; ++round) {
      const uint32_t v = rng() % size;
      set.insert(v);
      set.insert(v);  // inserting twice changes nothing
      reference.insert(v);
      const uint64_t lo = rng() % size, hi = lo + rng() % (size - lo + 1);
      const auto first = reference.lower_bound(static_cast<uint32_t>(lo));
      const uint64_t present =
          static_cast<uint64_t>(std::distance(first, reference.lower_bound(static_cast<uint32_t>(hi))));
      ASSERT_EQ(set.count_in(lo, hi), present) << "q=" << q << " [" << lo << ", " << hi << ")";
      ASSERT_EQ(set.count_below(size), reference.size());
      ASSERT_TRUE(set.contains(v));
      if (present > 0) {
        const uint64_t k = rng() % present;
        ASSERT_EQ(set.select(lo, k), *std::next(first, static_cast<long>(k))) << "q=" << q;
      }
      const uint64_t absent = (hi - lo) - present;
      if (absent > 0) {
        const uint64_t k = rng() % absent;
        uint64_t expected = lo, skipped = 0;
        for (;; ++expected)
          if (!reference.count(static_cast<uint32_t>(expected)) && skipped++ == k) break;
        ASSERT_EQ(set.select_absent(lo, k), expected) << "q=" << q << " lo=" << lo << " k=" << k;
      }
    }
  }
}

TEST(CoordinateSet, RejectsGridsItCannotHold) {
  EXPECT_DEATH(CoordinateSet(0), "qbits");
  EXPECT_DEATH(CoordinateSet(25), "qbits");
}

}  // namespace
}  // namespace dtm
