#include <gtest/gtest.h>

#include <cstring>

#include "fg/core/status.hpp"

TEST(Status, EveryValueHasAName) {
  EXPECT_STREQ(fg::to_string(fg::Status::ok), "ok");
  EXPECT_STREQ(fg::to_string(fg::Status::no_grasp), "no_grasp");
  EXPECT_STREQ(fg::to_string(fg::NoGraspReason::too_wide), "too_wide");
  EXPECT_STREQ(fg::to_string(static_cast<fg::Status>(12345)), "unknown_status");
}
