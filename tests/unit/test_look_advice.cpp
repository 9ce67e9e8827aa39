// Where a sensor would have to look after a refusal for occlusion
// (core/src/pipeline/look_advice.cpp): constructed sensors and hidden points whose
// answer follows from the geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "fg/core/pipeline/look_advice.hpp"

namespace {

using fg::Vec3;

// The sight maps are large: the views live on the heap.
std::unique_ptr<fg::SensorViews> two_sensors(const Vec3& head, const Vec3& hand) {
  auto s = std::make_unique<fg::SensorViews>();
  s->clear();
  s->added[0] = s->added[1] = true;
  s->origin[0] = head;
  s->origin[1] = hand;
  return s;
}

TEST(LookAdvice, LooksAtTheHiddenSpaceFromBeyondItAndAbove) {
  // A target centred at (0.5, 0, 0.05) on the plane z = 0; the space that refused it
  // lies 4 cm beyond its centre along +x, which both sensors look at from -x.
  const Vec3 centre(0.5f, 0.f, 0.05f), hidden(0.54f, 0.f, 0.05f);
  const auto s = two_sensors(Vec3(-0.2f, 0.f, 0.6f), Vec3(0.3f, -0.2f, 0.4f));
  const fg::LookAdvice a = fg::advise_look(hidden, centre, Vec3::UnitZ(), *s);
  ASSERT_TRUE(a.valid);
  EXPECT_TRUE(a.at.isApprox(hidden));
  const Vec3 d = a.from - a.at;
  // From the far side (+x), 45 deg above the plane, in the vertical plane through the
  // centre and the hidden space.
  EXPECT_GT(d.x(), 0.f);
  EXPECT_NEAR(d.y(), 0.f, 1e-6f);
  EXPECT_NEAR(std::atan2(d.z(), d.x()), fg::kLookElevationRad, 1e-5f);
  // The hand's direction from the hidden space is nearer the advised one than the
  // head's (from -x, behind the target): the hand moves, at its own distance.
  EXPECT_EQ(a.sensor, fg::SensorRole::hand);
  EXPECT_NEAR(d.norm(), (s->origin[1] - hidden).norm(), 1e-5f);
}

TEST(LookAdvice, TheSensorAlreadyNearestTheViewIsChosen) {
  // The head stands beyond the hidden space (+x, above), the hand behind the target.
  const Vec3 centre(0.5f, 0.f, 0.05f), hidden(0.5f, 0.04f, 0.05f);
  const auto s = two_sensors(Vec3(0.5f, 0.9f, 0.8f), Vec3(0.5f, -0.4f, 0.3f));
  const fg::LookAdvice a = fg::advise_look(hidden, centre, Vec3::UnitZ(), *s);
  ASSERT_TRUE(a.valid);
  EXPECT_EQ(a.sensor, fg::SensorRole::head);
  EXPECT_GT((a.from - a.at).y(), 0.f);
}

TEST(LookAdvice, OverTheCentreItLooksFromTheSideNoSensorIsOn) {
  // Hidden space straight above the target's centre: from away from the sensors.
  const Vec3 centre(0.5f, 0.f, 0.05f), hidden(0.5f, 0.f, 0.12f);
  const auto s = two_sensors(Vec3(-0.2f, 0.f, 0.6f), Vec3(0.2f, 0.1f, 0.5f));
  const fg::LookAdvice a = fg::advise_look(hidden, centre, Vec3::UnitZ(), *s);
  ASSERT_TRUE(a.valid);
  EXPECT_GT((a.from - a.at).x(), 0.f);
  EXPECT_GT((a.from - a.at).z(), 0.f);
}

TEST(LookAdvice, NoSensorNoAdvice) {
  auto s = std::make_unique<fg::SensorViews>();
  s->clear();
  EXPECT_FALSE(fg::advise_look(Vec3(0.5f, 0.f, 0.f), Vec3(0.45f, 0.f, 0.f), Vec3::UnitZ(), *s).valid);
}

}  // namespace
