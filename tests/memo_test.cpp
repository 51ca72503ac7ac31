// The memo the resolve loop's rebuilds share (core/memo.h): bounded, and keeping what the last
// rebuild used when the rebuilds together draw more than it holds.
#include "kerfab/core/memo.h"

#include <gtest/gtest.h>

#include <string>

#include "kerfab/pipeline/resolve.h"

namespace kerfab {
namespace {

struct Blob {
  std::size_t size = 0;
  std::size_t bytes() const { return size; }
};

std::string key(int i) { return "part " + std::to_string(i); }  // 6 to 9 bytes

// Rebuilds that each draw the same 40 parts and 40 new ones, 1 kB each, in a store of 100 kB:
// the 40 the rebuilds share are found every time after the first, although the store fills
// up every rebuild. (Emptied when full, as it was, it lost them in the rebuild after each
// emptying.)
TEST(Memo, WhatTheLastRebuildUsedStays) {
  Memo<Blob> memo(100'000);
  int fresh = 1000;
  for (int rebuild = 0; rebuild < 10; ++rebuild) {
    int found = 0;
    for (int part = 0; part < 40; ++part) {
      if (memo.find(key(part))) {
        ++found;
        continue;
      }
      memo.insert(key(part), Blob{1000});
    }
    for (int part = 0; part < 40; ++part) {
      const std::string k = key(fresh++);
      EXPECT_FALSE(memo.find(k));
      memo.insert(k, Blob{1000});
    }
    EXPECT_EQ(found, rebuild == 0 ? 0 : 40) << "rebuild " << rebuild;
    EXPECT_LE(memo.bytes(), 100'000u);
  }
  EXPECT_EQ(memo.hits(), 9u * 40);
  EXPECT_EQ(memo.misses(), 40u + 10 * 40);
}

// Never more than it may hold, and a value larger than that is not kept at all.
TEST(Memo, HoldsAtMostItsBound) {
  Memo<Blob> memo(10'000);
  for (int i = 0; i < 1000; ++i) {
    memo.insert(key(i), Blob{static_cast<std::size_t>(10 + i % 700)});
    ASSERT_LE(memo.bytes(), 10'000u);
  }
  memo.insert("large", Blob{9996});  // with its key, 10,001 bytes
  EXPECT_FALSE(memo.find("large"));
  memo.insert("fits", Blob{9996});  // 10,000 bytes: everything else goes
  EXPECT_TRUE(memo.find("fits"));
  EXPECT_EQ(memo.bytes(), 10'000u);
  EXPECT_FALSE(memo.find(key(999)));
  // An entry inserted twice counts once.
  Memo<Blob> once(10'000);
  once.insert("a", Blob{100});
  once.insert("a", Blob{100});
  EXPECT_EQ(once.bytes(), 101u);
}

// The run's budget for it: a thirty-second of --max-memory, within 80 MB (an eighth of a
// smaller budget) and 1 GB.
TEST(Memo, ARunsBudgetFollowsItsMemory) {
  constexpr std::size_t mb = 1 << 20;
  EXPECT_EQ(parts_memo_bytes(0), 80 * mb);
  EXPECT_EQ(parts_memo_bytes(12'800), 400 * mb);
  EXPECT_EQ(parts_memo_bytes(1000), 80 * mb);
  EXPECT_EQ(parts_memo_bytes(64), 8 * mb);
  EXPECT_EQ(parts_memo_bytes(1e6), 1024 * mb);
}

}  // namespace
}  // namespace kerfab
