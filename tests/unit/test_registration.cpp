// The registration stage (core/include/fg/core/pipeline/registration.hpp) on constructed
// scenes: a table and boxes ray-cast into both sensors' depth images (noise-free, whole
// millimetres), the hand's pose handed to the planner off by a known rigid error. The
// oracle is the true pose: after registration, a point the hand saw must land where it
// truly is, to within the millimetres the bins and the depth quantisation allow.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "fg/core/planner.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::Pose;
using fg::Vec3;

struct Box {
  Vec3 lo, hi;
};

// A table top (z = 0 over [0, 1] x [-0.5, 0.5]) and axis-aligned boxes on it.
struct Ball {
  Vec3 c;
  float r;
};
struct World {
  std::vector<Box> boxes;
  std::vector<Ball> balls;
  bool table = true;
};

// Nearest hit along the ray o + s d (s > 0); false when none.
bool cast(const World& w, const Vec3& o, const Vec3& d, float& s) {
  float best = 1e30f;
  if (w.table && d.z() < 0.f) {
    const float t = -o.z() / d.z();
    const Vec3 p = o + t * d;
    if (t > 0.f && p.x() >= 0.f && p.x() <= 1.f && std::fabs(p.y()) <= 0.5f) best = t;
  }
  for (const Box& b : w.boxes) {  // slabs
    float t0 = 0.f, t1 = 1e30f;
    bool hit = true;
    for (int j = 0; j < 3 && hit; ++j) {
      if (std::fabs(d[j]) < 1e-12f) {
        hit = o[j] >= b.lo[j] && o[j] <= b.hi[j];
        continue;
      }
      float a = (b.lo[j] - o[j]) / d[j], c = (b.hi[j] - o[j]) / d[j];
      if (a > c) std::swap(a, c);
      t0 = std::max(t0, a);
      t1 = std::min(t1, c);
      hit = t0 <= t1;
    }
    if (hit && t0 > 0.f && t0 < best) best = t0;
  }
  for (const Ball& b : w.balls) {  // |o + s d - c| = r, d of any length
    const Vec3 oc = o - b.c;
    const float a = d.squaredNorm(), half_b = oc.dot(d), c = oc.squaredNorm() - b.r * b.r;
    const float disc = half_b * half_b - a * c;
    if (disc < 0.f) continue;
    const float t = (-half_b - std::sqrt(disc)) / a;
    if (t > 0.f && t < best) best = t;
  }
  s = best;
  return best < 1e29f;
}

constexpr uint16_t kW = 320, kH = 240;
const fg::PinholeIntrinsics kK{280.f, 280.f, 159.5f, 119.5f};

// The depth image (mm along the optical axis) a sensor at `pose` sees of the world.
std::vector<uint16_t> render(const World& w, const Pose& pose) {
  std::vector<uint16_t> img(size_t{kW} * kH, 0);
  for (uint16_t v = 0; v < kH; ++v)
    for (uint16_t u = 0; u < kW; ++u) {
      const Vec3 ray((static_cast<float>(u) - kK.cx) / kK.fx, (static_cast<float>(v) - kK.cy) / kK.fy, 1.f);
      float s = 0.f;
      if (!cast(w, pose.t, pose.R * ray, s)) continue;
      const float mm = std::round(s * 1000.f);  // ray's z is 1: s is the depth
      if (mm > 0.f && mm < 65535.f) img[size_t{v} * kW + u] = static_cast<uint16_t>(mm);
    }
  return img;
}

// The pose off by a rigid error in its own frame: turned by `deg` about `axis`, moved by `mm` along `dir`.
Pose off_by(const Pose& p, const Vec3& dir, float mm, const Vec3& axis, float deg) {
  Pose q;
  const fg::Mat3 dR = Eigen::AngleAxisf(deg * 3.14159265f / 180.f, axis.normalized()).toRotationMatrix();
  q.R = p.R * dR;
  q.t = p.t + p.R * (dir.normalized() * (mm * 1e-3f));
  return q;
}

// Where a world point the hand truly sees lands with the pose the planner used (m).
float error_at(const Pose& truth, const Pose& used, const Vec3& world) {
  const Vec3 in_sensor = truth.R.transpose() * (world - truth.t);
  return (used.apply(in_sensor) - world).norm();
}

// Boxes whose sides face every horizontal direction, so that every direction of the
// hand's error is seen.
World boxes_world() {
  World w;
  w.boxes.push_back({Vec3(0.42f, -0.08f, 0.f), Vec3(0.50f, -0.02f, 0.12f)});
  w.boxes.push_back({Vec3(0.55f, 0.03f, 0.f), Vec3(0.60f, 0.11f, 0.08f)});
  w.boxes.push_back({Vec3(0.47f, 0.07f, 0.f), Vec3(0.52f, 0.10f, 0.15f)});
  return w;
}

const Pose kHead = fg::test::look_at(Vec3(-0.15f, 0.25f, 0.75f), Vec3(0.5f, 0.f, 0.05f));
const Pose kHand = fg::test::look_at(Vec3(0.26f, 0.24f, 0.42f), Vec3(0.52f, 0.0f, 0.05f));
const Vec3 kCentre(0.51f, 0.02f, 0.06f);

struct Outcome {
  fg::Status plan_status = fg::Status::internal_error;
  fg::PlanResult result;
  Pose hand_used;
};

// Both sensors' images of the world from their true poses (kHead, kHand unless stated),
// the hand's pose and the head's given as stated. A sensor a disagreement left out
// cannot be added again.
Outcome run(const World& w, const Pose& hand_given, fg::RegistrationMode mode, bool head_first = true,
            const Pose& head_given = kHead, const Pose& head_true = kHead, const Pose& hand_true = kHand) {
  auto planner = std::make_unique<fg::Planner>();
  EXPECT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  planner->set_registration(mode);
  const std::vector<uint16_t> head = render(w, head_true), hand = render(w, hand_true);
  const auto add = [&](fg::SensorRole role, const Pose& pose) {
    const std::vector<uint16_t>& image = role == fg::SensorRole::head ? head : hand;
    return planner->add_depth_image(role, image.data(), kW, kH, kK, pose);
  };
  const fg::SensorRole first = head_first ? fg::SensorRole::head : fg::SensorRole::hand;
  const fg::SensorRole second = head_first ? fg::SensorRole::hand : fg::SensorRole::head;
  const auto given = [&](fg::SensorRole role) { return role == fg::SensorRole::head ? head_given : hand_given; };
  EXPECT_EQ(add(first, given(first)), fg::Status::ok);
  EXPECT_EQ(add(second, given(second)), fg::Status::ok);
  const fg::RegistrationResult& reg = planner->registration();
  if (reg.outcome == fg::RegistrationOutcome::sensor_disagreement) {
    EXPECT_EQ(add(reg.left_out, given(reg.left_out)), fg::Status::invalid_sensor);
  }
  Outcome r;
  r.plan_status = planner->plan(r.result);
  r.hand_used = planner->sensor_pose(fg::SensorRole::hand);
  return r;
}

// Both sensors' images from their true poses `head` and `hand` (given as they are), the
// hand's pose given as `hand_given`, registration on.
Outcome run_between(const World& w, const Pose& head, const Pose& hand, const Pose& hand_given) {
  return run(w, hand_given, fg::RegistrationMode::on, true, head, head, hand);
}

TEST(Registration, CorrectsAHandPoseOffByMillimetresAndADegree) {
  const World w = boxes_world();
  const struct {
    Vec3 dir;
    float mm;
    Vec3 axis;
    float deg;
  } cases[] = {{Vec3(1, 0, 0), 10.f, Vec3(0, 1, 0), 1.f},
               {Vec3(0, 1, 1), 8.f, Vec3(1, 0, 0), 0.5f},
               {Vec3(1, -1, 0), 15.f, Vec3(0, 0, 1), 1.5f},
               {Vec3(-1, 2, 1), 12.f, Vec3(1, 1, 1), 1.f}};
  for (const auto& c : cases) {
    const Pose given = off_by(kHand, c.dir, c.mm, c.axis, c.deg);
    const Outcome r = run(w, given, fg::RegistrationMode::on);
    const fg::RegistrationResult& reg = r.result.registration;
    const float before = error_at(kHand, given, kCentre), after = error_at(kHand, r.hand_used, kCentre);
    EXPECT_EQ(reg.outcome, fg::RegistrationOutcome::corrected) << c.mm << " mm";
    EXPECT_GT(before, 0.005f);
    // A few millimetres are left: the bins' half-resolution, the whole-millimetre depths
    // and the boxes' small sides, which hold the turn about the vertical only weakly.
    EXPECT_LT(after, 0.0025f) << c.mm << " mm, " << c.deg << " deg: " << before * 1e3f << " mm before";
    EXPECT_LT(after, 0.3f * before);
    // Across the boxes too, not only at their centre.
    for (const Box& b : w.boxes) EXPECT_LT(error_at(kHand, r.hand_used, 0.5f * (b.lo + b.hi)), 0.004f);
    EXPECT_LT(reg.residual_mm, reg.residual_before_mm);
    EXPECT_GT(reg.pairs, 64u);
    EXPECT_LE(reg.iterations, fg::RegistrationParams{}.max_iterations);
  }
}

// The hand's points of a depth image, in the sensor's frame, pixel by pixel.
std::vector<float> points_of(const std::vector<uint16_t>& img) {
  std::vector<float> xyz;
  for (uint16_t v = 0; v < kH; ++v)
    for (uint16_t u = 0; u < kW; ++u) {
      const float z = static_cast<float>(img[size_t{v} * kW + u]) * 0.001f;
      if (img[size_t{v} * kW + u] == 0) {  // no return: a NaN point, as an organized cloud has
        for (int k = 0; k < 3; ++k) xyz.push_back(std::nanf(""));
        continue;
      }
      xyz.push_back((static_cast<float>(u) - kK.cx) / kK.fx * z);
      xyz.push_back((static_cast<float>(v) - kK.cy) / kK.fy * z);
      xyz.push_back(z);
    }
  return xyz;
}

// xyz triples handed over in pieces of `piece` points; it can start again.
class Pieces final : public fg::PointSource {
 public:
  Pieces(const std::vector<float>& xyz, uint32_t piece) : xyz_(xyz), piece_(piece) {}
  bool next(fg::PointPiece& p) override {
    const uint32_t total = static_cast<uint32_t>(xyz_.size() / 3);
    const uint32_t n = std::min(piece_, total - at_);
    const auto* base = reinterpret_cast<const uint8_t*>(xyz_.data() + size_t{3} * at_);
    p = fg::PointPiece{base, base + 4, base + 8, 12, n};
    at_ += n;
    return true;
  }
  bool can_rewind() const override { return true; }
  bool rewind() override {
    at_ = 0;
    return true;
  }

 private:
  const std::vector<float>& xyz_;
  uint32_t piece_;
  uint32_t at_ = 0;
};

// The first pass reads every fourth point with a depth of the hand's cloud, counted
// across the pieces a source hands over: pieces of any size, the depth image itself and
// its points without those that have no return give the registration of the whole.
TEST(Registration, ReadsTheSamePointsWholeOrInPieces) {
  const World w = boxes_world();
  const Pose given = off_by(kHand, Vec3(1, 0, 0), 10.f, Vec3(0, 1, 0), 1.f);
  const std::vector<uint16_t> head = render(w, kHead), hand_image = render(w, kHand);
  const std::vector<float> hand = points_of(hand_image);
  std::vector<float> with_return;  // the points that have a return
  for (size_t i = 0; i + 2 < hand.size(); i += 3)
    if (!std::isnan(hand[i + 2]))
      with_return.insert(with_return.end(), hand.begin() + static_cast<long>(i),
                         hand.begin() + static_cast<long>(i) + 3);
  enum class Input { whole, pieces, image, returns };
  const struct {
    Input input;
    uint32_t piece;
  } cases[] = {{Input::whole, 0},  {Input::pieces, 1001}, {Input::pieces, 4099},
               {Input::pieces, 3}, {Input::image, 0},     {Input::returns, 0}};
  std::vector<fg::RegistrationResult> reg;
  for (const auto& c : cases) {
    auto planner = std::make_unique<fg::Planner>();
    ASSERT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
    ASSERT_EQ(planner->add_depth_image(fg::SensorRole::head, head.data(), kW, kH, kK, kHead), fg::Status::ok);
    const auto add = [&](const std::vector<float>& xyz) {
      return planner->add_points(fg::SensorRole::hand, xyz.data(), static_cast<uint32_t>(xyz.size() / 3), 12, given);
    };
    fg::Status st = fg::Status::ok;
    if (c.input == Input::whole) {
      st = add(hand);
    } else if (c.input == Input::returns) {
      st = add(with_return);
    } else if (c.input == Input::image) {
      st = planner->add_depth_image(fg::SensorRole::hand, hand_image.data(), kW, kH, kK, given);
    } else {
      Pieces src(hand, c.piece);
      st = planner->add_point_source(fg::SensorRole::hand, src, given);
    }
    ASSERT_EQ(st, fg::Status::ok);
    fg::PlanResult r;
    (void)planner->plan(r);
    reg.push_back(r.registration);
  }
  EXPECT_EQ(reg[0].outcome, fg::RegistrationOutcome::corrected);
  for (size_t k = 1; k < reg.size(); ++k) {
    EXPECT_EQ(reg[k].outcome, reg[0].outcome) << k;
    EXPECT_EQ(reg[k].pairs, reg[0].pairs) << k;
    EXPECT_EQ(reg[k].samples, reg[0].samples) << k;
    EXPECT_EQ(reg[k].residual_mm, reg[0].residual_mm) << k;
    EXPECT_EQ(reg[k].translation_mm, reg[0].translation_mm) << k;
  }
}

TEST(Registration, KeepsAnExactCalibrationAndItsPlan) {
  const World w = boxes_world();
  const Outcome on = run(w, kHand, fg::RegistrationMode::on);
  const Outcome off = run(w, kHand, fg::RegistrationMode::off);
  EXPECT_EQ(on.result.registration.outcome, fg::RegistrationOutcome::calibration_kept);
  EXPECT_EQ(off.result.registration.outcome, fg::RegistrationOutcome::not_run);
  EXPECT_EQ((on.hand_used.t - kHand.t).norm(), 0.f);
  EXPECT_EQ((on.hand_used.R - kHand.R).norm(), 0.f);
  // Nothing seen through: the clouds agree.
  EXPECT_GE(on.result.registration.compared, fg::RegistrationParams{}.min_pairs);
  EXPECT_LT(on.result.registration.see_through, 0.05f);
  // The same grid, so the same plan, bit for bit.
  ASSERT_EQ(on.plan_status, off.plan_status);
  EXPECT_EQ(on.result.points.voxels, off.result.points.voxels);
  EXPECT_EQ(on.result.grasp.position, off.result.grasp.position);
  EXPECT_EQ(on.result.grasp.closing, off.result.grasp.closing);
  EXPECT_EQ(on.result.grasp.width, off.result.grasp.width);
}

TEST(Registration, DoesNotSlideWhatOnlyABareTableShows) {
  // A bare table fixes height and tilt only: a slide along it is not seen, so none is
  // made up, while the height error is corrected.
  World w;
  const Pose given = off_by(kHand, kHand.R.transpose() * Vec3(1.f, 0.f, 0.f), 12.f, Vec3(0, 0, 1), 0.f);
  Pose lifted = given;
  lifted.t += Vec3(0.f, 0.f, 0.008f);  // and 8 mm too high
  const Outcome r = run(w, lifted, fg::RegistrationMode::on);
  const fg::RegistrationResult& reg = r.result.registration;
  ASSERT_EQ(reg.outcome, fg::RegistrationOutcome::corrected);
  EXPECT_NEAR(reg.correction.t.z(), -0.008f, 0.0015f);
  // The hand's origin moved (nearly) straight down: no slide along the table.
  const Vec3 moved = r.hand_used.t - lifted.t;
  EXPECT_LT(std::hypot(moved.x(), moved.y()), 0.002f) << moved.transpose();
}

TEST(Registration, FindsTheSlideOnRoundBodiesSeenFromOppositeSides) {
  // Sensors on opposite sides of three balls on a table: each sees the halves facing it,
  // and both only the caps. The table and the caps fix the height and the tilt; the
  // caps' slopes are all that shows a slide along the table, too few pairs for the
  // point-to-plane alignment to move there (kMinInformation), so the search for the
  // slide must find it. The hand's bins (8 mm here) blur the caps' outlines, so a few
  // millimetres may be left, but never more than before.
  World w;
  w.balls.push_back({Vec3(0.46f, -0.08f, 0.05f), 0.05f});
  w.balls.push_back({Vec3(0.58f, 0.00f, 0.06f), 0.06f});
  w.balls.push_back({Vec3(0.44f, 0.08f, 0.045f), 0.045f});
  const Vec3 centre(0.5f, 0.f, 0.05f);
  const Pose head = fg::test::look_at(Vec3(0.08f, -0.30f, 0.62f), centre);
  const Pose hand = fg::test::look_at(Vec3(0.80f, 0.25f, 0.40f), centre);
  const Vec3 slides[] = {Vec3(0.010f, 0.f, 0.f), Vec3(0.f, -0.008f, 0.f), Vec3(-0.007f, 0.009f, 0.f),
                         Vec3(0.006f, 0.006f, 0.003f), Vec3(-0.012f, -0.004f, 0.f)};
  float sum_before = 0.f, sum_after = 0.f;
  for (const Vec3& slide : slides) {
    Pose given = hand;
    given.t += slide;
    const Outcome r = run_between(w, head, hand, given);
    const float before = error_at(hand, given, centre), after = error_at(hand, r.hand_used, centre);
    EXPECT_LT(after, before + 0.0005f) << slide.transpose() << ": " << before * 1e3f << " mm before, " << after * 1e3f
                                       << " after";
    sum_before += before;
    sum_after += after;
  }
  EXPECT_LT(sum_after, 0.6f * sum_before) << sum_after * 1e3f << " mm after, " << sum_before * 1e3f << " before";
  // With the poses exact, nothing moves.
  const Outcome exact = run_between(w, head, hand, hand);
  EXPECT_EQ(exact.result.registration.outcome, fg::RegistrationOutcome::calibration_kept);
  EXPECT_EQ((exact.hand_used.t - hand.t).norm(), 0.f);
}

TEST(Registration, RunsOnlyWithTheHeadFirstAndWhenOn) {
  const World w = boxes_world();
  const Pose given = off_by(kHand, Vec3(1, 0, 0), 10.f, Vec3(0, 1, 0), 1.f);
  const Outcome first = run(w, given, fg::RegistrationMode::on, false);
  EXPECT_EQ(first.result.registration.outcome, fg::RegistrationOutcome::hand_added_first);
  EXPECT_EQ((first.hand_used.t - given.t).norm(), 0.f);
  const Outcome off = run(w, given, fg::RegistrationMode::off);
  EXPECT_EQ(off.result.registration.outcome, fg::RegistrationOutcome::not_run);
  EXPECT_EQ((off.hand_used.t - given.t).norm(), 0.f);
}

// The plan of the head's image alone.
// One sensor's image alone, at its true pose.
Outcome run_alone(const World& w, fg::SensorRole role) {
  auto planner = std::make_unique<fg::Planner>();
  EXPECT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  const Pose& pose = role == fg::SensorRole::head ? kHead : kHand;
  const std::vector<uint16_t> image = render(w, pose);
  EXPECT_EQ(planner->add_depth_image(role, image.data(), kW, kH, kK, pose), fg::Status::ok);
  Outcome r;
  r.plan_status = planner->plan(r.result);
  return r;
}

// The plan of `r` is the one sensor's alone, bit for bit: the same grid, the same grasp.
void expect_same_plan(const Outcome& r, const Outcome& alone) {
  ASSERT_EQ(r.plan_status, alone.plan_status);
  EXPECT_EQ(r.result.points.voxels, alone.result.points.voxels);
  EXPECT_EQ(r.result.grasp.position, alone.result.grasp.position);
  EXPECT_EQ(r.result.grasp.closing, alone.result.grasp.closing);
}

TEST(Registration, LeavesOutAHandThatSeesThroughTheHeadsSurfaces) {
  // 12 cm and 8 degrees off, beyond the alignment's reach: the hand's surfaces lie
  // where the head saw through, and the head's where the hand did. The plan is the
  // head's alone, bit for bit.
  const World w = boxes_world();
  const Pose given = off_by(kHand, Vec3(1, 1, 0), 120.f, Vec3(0, 0, 1), 8.f);
  const Outcome r = run(w, given, fg::RegistrationMode::on);
  const fg::RegistrationResult& reg = r.result.registration;
  EXPECT_EQ(reg.outcome, fg::RegistrationOutcome::sensor_disagreement) << fg::to_string(reg.outcome);
  EXPECT_GT(reg.see_through, fg::RegistrationParams{}.max_see_through);
  EXPECT_GE(reg.compared, fg::RegistrationParams{}.min_pairs);
  EXPECT_EQ(reg.correction.t.norm(), 0.f);
  EXPECT_EQ((r.hand_used.t - given.t).norm(), 0.f);
  expect_same_plan(r, run_alone(w, fg::SensorRole::head));
}

TEST(Registration, LeavesOutAHeadWhoseTableIsOffLevel) {
  // The head turned 7 degrees about its horizontal image axis (a head knocked out of
  // its calibration): its table leans 7 degrees and its boxes lie centimetres off, beyond
  // the alignment's reach. The hand's table is level, as the world's is: the head's
  // points leave the grid and the plan is the hand's alone, bit for bit.
  const World w = boxes_world();
  const Pose head_given = off_by(kHead, Vec3(1, 0, 0), 0.f, Vec3(1, 0, 0), 7.f);
  const Outcome r = run(w, kHand, fg::RegistrationMode::on, true, head_given);
  const fg::RegistrationResult& reg = r.result.registration;
  ASSERT_EQ(reg.outcome, fg::RegistrationOutcome::sensor_disagreement) << fg::to_string(reg.outcome);
  EXPECT_EQ(reg.left_out, fg::SensorRole::head);
  EXPECT_NEAR(reg.head_tilt_deg, 7.f, 1.f);
  EXPECT_LT(reg.hand_tilt_deg, 1.f);
  EXPECT_EQ((r.hand_used.t - kHand.t).norm(), 0.f);
  expect_same_plan(r, run_alone(w, fg::SensorRole::hand));
}

TEST(Registration, KeepsTheHeadWhenTheHandsTableIsOffLevel) {
  // The other way round (the hand turned about its horizontal image axis): the hand's
  // table leans, the head's is level, and the hand is the one left out.
  const World w = boxes_world();
  const Pose given = off_by(kHand, Vec3(0, 1, 0), 60.f, Vec3(1, 0, 0), 8.f);
  const Outcome r = run(w, given, fg::RegistrationMode::on);
  const fg::RegistrationResult& reg = r.result.registration;
  ASSERT_EQ(reg.outcome, fg::RegistrationOutcome::sensor_disagreement) << fg::to_string(reg.outcome);
  EXPECT_EQ(reg.left_out, fg::SensorRole::hand);
  EXPECT_LT(reg.head_tilt_deg, 1.f);
  EXPECT_GT(reg.hand_tilt_deg, 3.f);
  expect_same_plan(r, run_alone(w, fg::SensorRole::head));
}

TEST(Registration, CatchesASeeThroughEitherWay) {
  // The hand 8 cm off along its line of sight: pushed away, its surfaces lie behind the
  // head's samples (the hand saw through them); pulled back, in front of them, where
  // the head saw past.
  const World w = boxes_world();
  for (const float mm : {80.f, -80.f}) {
    const Pose given = off_by(kHand, Vec3(0, 0, 1), mm, Vec3(0, 0, 1), 0.f);
    const Outcome r = run(w, given, fg::RegistrationMode::on);
    EXPECT_EQ(r.result.registration.outcome, fg::RegistrationOutcome::sensor_disagreement)
        << mm << " mm: " << fg::to_string(r.result.registration.outcome) << ", see-through "
        << r.result.registration.see_through;
  }
}

TEST(Registration, StrictMakesADisagreementAnError) {
  const World w = boxes_world();
  const Pose given = off_by(kHand, Vec3(1, 1, 0), 120.f, Vec3(0, 0, 1), 8.f);
  auto planner = std::make_unique<fg::Planner>();
  ASSERT_EQ(planner->configure(fg::PlannerConfig{}), fg::Status::ok);
  planner->set_registration(fg::RegistrationMode::strict);
  const std::vector<uint16_t> head = render(w, kHead), hand = render(w, kHand);
  ASSERT_EQ(planner->add_depth_image(fg::SensorRole::head, head.data(), kW, kH, kK, kHead), fg::Status::ok);
  ASSERT_EQ(planner->add_depth_image(fg::SensorRole::hand, hand.data(), kW, kH, kK, given), fg::Status::ok);
  // Left out, the hand is still added: a second hand is refused.
  EXPECT_EQ(planner->add_depth_image(fg::SensorRole::hand, hand.data(), kW, kH, kK, kHand), fg::Status::invalid_sensor);
  fg::PlanResult res;
  EXPECT_EQ(planner->plan(res), fg::Status::sensor_disagreement);
  EXPECT_NE(std::string(res.message).find("disagrees"), std::string::npos) << res.message;
  EXPECT_EQ(res.registration.outcome, fg::RegistrationOutcome::sensor_disagreement);
  // An exact calibration plans in strict mode as in the default one.
  const Outcome exact = run(w, kHand, fg::RegistrationMode::strict), on = run(w, kHand, fg::RegistrationMode::on);
  ASSERT_EQ(exact.plan_status, on.plan_status);
  EXPECT_EQ(exact.result.grasp.position, on.result.grasp.position);
}

TEST(Registration, OutcomesHaveNames) {
  for (auto o :
       {fg::RegistrationOutcome::not_run, fg::RegistrationOutcome::corrected, fg::RegistrationOutcome::calibration_kept,
        fg::RegistrationOutcome::too_little_overlap, fg::RegistrationOutcome::implausible,
        fg::RegistrationOutcome::hand_added_first, fg::RegistrationOutcome::sensor_disagreement})
    EXPECT_STRNE(fg::to_string(o), "unknown");
}

}  // namespace
