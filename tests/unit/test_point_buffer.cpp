// PointBuffer<N> / PointBufferExt / PointSpan: capacity, the checked push (full ->
// capacity_exceeded with the data left intact), caller memory (null -> capacity 0)
// and size-erased use through PointSpan&.
#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>
#include <vector>

#include "fg/core/point_buffer.hpp"

namespace {

using fg::PointBuffer;
using fg::PointBufferExt;
using fg::PointSpan;
using fg::Status;
using fg::Vec3;

Vec3 pt(uint32_t i) { return Vec3(static_cast<float>(i), 0.5f * static_cast<float>(i), -1.f * static_cast<float>(i)); }

bool same(const Vec3& a, const Vec3& b) { return a.x() == b.x() && a.y() == b.y() && a.z() == b.z(); }

// Fills a span through the size-erased base only; returns how many pushes succeeded.
uint32_t fill_through_base(PointSpan& s, uint32_t attempts) {
  uint32_t ok = 0;
  for (uint32_t i = 0; i < attempts; ++i) {
    if (s.push(pt(i)) == Status::ok) ++ok;
  }
  return ok;
}

TEST(PointBuffer, StartsEmptyWithTemplateCapacity) {
  PointBuffer<7> b;
  EXPECT_EQ(b.capacity(), 7u);
  EXPECT_EQ(b.size(), 0u);
  EXPECT_TRUE(b.empty());
  EXPECT_FALSE(b.full());
  EXPECT_EQ(b.begin(), b.end());
  EXPECT_NE(b.data(), nullptr);
}

TEST(PointBuffer, CapacityOne) {
  PointBuffer<1> b;
  EXPECT_EQ(b.capacity(), 1u);
  EXPECT_EQ(b.push(pt(3)), Status::ok);
  EXPECT_TRUE(b.full());
  EXPECT_EQ(b.push(pt(4)), Status::capacity_exceeded);
  EXPECT_EQ(b.size(), 1u);
  EXPECT_TRUE(same(b[0], pt(3)));
}

TEST(PointBuffer, PushUntilFullThenRejectsAndKeepsData) {
  PointBuffer<16> b;
  for (uint32_t i = 0; i < 16; ++i) {
    ASSERT_EQ(b.push(pt(i)), Status::ok) << i;
    EXPECT_EQ(b.size(), i + 1);
  }
  EXPECT_TRUE(b.full());
  for (int extra = 0; extra < 5; ++extra) {
    EXPECT_EQ(b.push(Vec3(99.f, 99.f, 99.f)), Status::capacity_exceeded);
    EXPECT_EQ(b.size(), 16u);
  }
  for (uint32_t i = 0; i < 16; ++i) EXPECT_TRUE(same(b[i], pt(i))) << i;
  // begin/end walk exactly the stored points.
  uint32_t k = 0;
  for (const Vec3& p : static_cast<const PointSpan&>(b)) {
    EXPECT_TRUE(same(p, pt(k)));
    ++k;
  }
  EXPECT_EQ(k, 16u);
  EXPECT_EQ(b.end() - b.begin(), 16);
}

TEST(PointBuffer, ClearMakesRoomAgain) {
  PointBuffer<4> b;
  for (uint32_t i = 0; i < 4; ++i) ASSERT_EQ(b.push(pt(i)), Status::ok);
  b.clear();
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.capacity(), 4u);
  for (uint32_t i = 10; i < 14; ++i) ASSERT_EQ(b.push(pt(i)), Status::ok);
  EXPECT_EQ(b.push(pt(0)), Status::capacity_exceeded);
  for (uint32_t i = 0; i < 4; ++i) EXPECT_TRUE(same(b[i], pt(10 + i)));
}

TEST(PointBuffer, ElementsAreWritableInPlace) {
  PointBuffer<3> b;
  ASSERT_EQ(b.push(pt(1)), Status::ok);
  b[0] = Vec3(7.f, 8.f, 9.f);
  EXPECT_TRUE(same(b.data()[0], Vec3(7.f, 8.f, 9.f)));
}

TEST(PointBufferExt, UsesCallerMemory) {
  std::vector<Vec3> mem(10, Vec3(-5.f, -5.f, -5.f));
  PointBufferExt b(mem.data(), 10);
  EXPECT_EQ(b.capacity(), 10u);
  EXPECT_EQ(b.size(), 0u);
  EXPECT_EQ(b.data(), mem.data());
  for (uint32_t i = 0; i < 10; ++i) ASSERT_EQ(b.push(pt(i)), Status::ok);
  EXPECT_EQ(b.push(pt(100)), Status::capacity_exceeded);
  EXPECT_EQ(b.size(), 10u);
  for (uint32_t i = 0; i < 10; ++i) EXPECT_TRUE(same(mem[i], pt(i))) << i;
}

TEST(PointBufferExt, DoesNotWriteBeyondItsCapacity) {
  // The buffer is told it has 4 slots of a 6-slot array: slots 4 and 5 stay untouched.
  std::vector<Vec3> mem(6, Vec3(-5.f, -5.f, -5.f));
  PointBufferExt b(mem.data(), 4);
  for (uint32_t i = 0; i < 8; ++i) (void)b.push(pt(i));
  EXPECT_EQ(b.size(), 4u);
  EXPECT_TRUE(same(mem[4], Vec3(-5.f, -5.f, -5.f)));
  EXPECT_TRUE(same(mem[5], Vec3(-5.f, -5.f, -5.f)));
}

TEST(PointBufferExt, NullMemoryHasCapacityZero) {
  PointBufferExt b(nullptr, 1000);
  EXPECT_EQ(b.capacity(), 0u);
  EXPECT_EQ(b.size(), 0u);
  EXPECT_TRUE(b.empty());
  EXPECT_TRUE(b.full());
  EXPECT_EQ(b.push(pt(1)), Status::capacity_exceeded);
  EXPECT_EQ(b.size(), 0u);
  EXPECT_EQ(b.begin(), b.end());
}

TEST(PointBufferExt, ZeroCapacityOverRealMemory) {
  Vec3 one(1.f, 2.f, 3.f);
  PointBufferExt b(&one, 0);
  EXPECT_EQ(b.capacity(), 0u);
  EXPECT_EQ(b.push(pt(4)), Status::capacity_exceeded);
  EXPECT_TRUE(same(one, Vec3(1.f, 2.f, 3.f)));
}

TEST(PointSpan, SizeErasedUseOfBothKinds) {
  PointBuffer<5> inside;
  std::vector<Vec3> mem(3);
  PointBufferExt outside(mem.data(), 3);
  PointSpan* spans[2] = {&inside, &outside};
  const uint32_t caps[2] = {5, 3};
  for (int s = 0; s < 2; ++s) {
    PointSpan& span = *spans[s];
    EXPECT_EQ(span.capacity(), caps[s]);
    EXPECT_EQ(fill_through_base(span, 9), caps[s]);
    EXPECT_EQ(span.size(), caps[s]);
    EXPECT_TRUE(span.full());
    for (uint32_t i = 0; i < caps[s]; ++i) EXPECT_TRUE(same(span[i], pt(i)));
    span.clear();
    EXPECT_TRUE(span.empty());
    EXPECT_EQ(fill_through_base(span, 2), 2u);
  }
}

TEST(PointSpan, NotCopyable) {
  static_assert(!std::is_copy_constructible<PointSpan>::value, "PointSpan must not copy");
  static_assert(!std::is_copy_assignable<PointSpan>::value, "PointSpan must not copy");
  static_assert(!std::is_copy_constructible<PointBuffer<4>>::value, "PointBuffer must not copy");
  static_assert(!std::is_copy_constructible<PointBufferExt>::value, "PointBufferExt must not copy");
  // PointBuffer<N> keeps its storage inside: no pointer to outside memory.
  static_assert(sizeof(PointBuffer<64>) >= 64 * sizeof(Vec3), "storage is inside the object");
  SUCCEED();
}

}  // namespace
