// segment_meets_box (the slab test under fingers_clear_of_footprint) against a brute
// force: the segment sampled densely, each sample tested for containment.
#include <gtest/gtest.h>

#include <random>

#include "fg/core/segment_box.hpp"

namespace {

// Whether some of n + 1 evenly spaced samples of the segment lies in the box grown by
// `grow` on every side (negative: shrunk).
bool sampled_hit(const float q[3], const float dir[3], float u0, float u1, const float lo[3], const float hi[3],
                 float grow, int n) {
  if (u0 > u1) return false;  // an empty segment
  for (int k = 0; k <= n; ++k) {
    const float u = u0 + (u1 - u0) * static_cast<float>(k) / static_cast<float>(n);
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const float p = q[a] - u * dir[a];
      inside = inside && p >= lo[a] - grow && p <= hi[a] + grow;
    }
    if (inside) return true;
  }
  return false;
}

}  // namespace

TEST(SegmentBox, AgreesWithDenseSampling) {
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<float> pos(-0.1f, 0.1f), ext(0.002f, 0.05f), frac(0.f, 1.f);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    float q[3], dir[3], lo[3], hi[3], aim[3];
    for (int a = 0; a < 3; ++a) {
      q[a] = pos(rng);
      lo[a] = pos(rng);
      hi[a] = lo[a] + ext(rng);
      // The line is aimed at a point near the box (inside it about a third of the time).
      aim[a] = lo[a] + (hi[a] - lo[a]) * (2.f * frac(rng) - 0.5f);
      dir[a] = q[a] - aim[a];  // q - 1 * dir = aim
    }
    // A third of the trials have an axis along which the segment does not move (the
    // planner's vertical line is parallel to a grasp axis when the closing is vertical).
    if (trial % 3 == 0) dir[trial % 9 / 3] = 0.f;
    const float u0 = 2.f * frac(rng), u1 = u0 + 2.f * frac(rng) - 0.2f;  // sometimes empty
    const bool slab = fg::segment_meets_box(q, dir, u0, u1, lo, hi);
    // Only where the samples decide with a margin: clearly in, or clearly out.
    if (sampled_hit(q, dir, u0, u1, lo, hi, -1e-4f, 20000)) {
      EXPECT_TRUE(slab) << "trial " << trial;
      ++hits;
    } else if (!sampled_hit(q, dir, u0, u1, lo, hi, 1e-4f, 20000)) {
      EXPECT_FALSE(slab) << "trial " << trial;
      ++misses;
    }
  }
  // Both answers are exercised often.
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
}

TEST(SegmentBox, VerticalLineUnderAPoint) {
  const float lo[3] = {-0.01f, -0.01f, -0.01f}, hi[3] = {0.01f, 0.01f, 0.01f};
  const float down[3] = {0.f, 0.f, 1.f};  // q - u * dir goes down in z
  const float above[3] = {0.f, 0.f, 0.05f};
  EXPECT_TRUE(fg::segment_meets_box(above, down, 0.005f, 0.2f, lo, hi));
  EXPECT_FALSE(fg::segment_meets_box(above, down, 0.005f, 0.03f, lo, hi));  // ends 2 cm above
  EXPECT_TRUE(fg::segment_meets_box(above, down, 0.005f, 0.04f, lo, hi));   // ends on the top
  const float beside[3] = {0.02f, 0.f, 0.05f};
  EXPECT_FALSE(fg::segment_meets_box(beside, down, 0.005f, 0.2f, lo, hi));  // parallel, outside
  const float below[3] = {0.f, 0.f, -0.05f};
  EXPECT_FALSE(fg::segment_meets_box(below, down, 0.005f, 0.2f, lo, hi));  // goes away from it
  EXPECT_FALSE(fg::segment_meets_box(above, down, 0.2f, 0.1f, lo, hi));    // empty interval
}
