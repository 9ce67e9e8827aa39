// The units of a sensor's points (Planner::set_sensor_units, pipeline/units.hpp): a
// cloud in millimetres, centimetres or 1000 times too small is refused naming its
// units, whatever way its points arrive; declared units plan as metres do (bit for bit
// at a power-of-two scale); a cloud that merely lies beyond the range is no such
// mistake; depth images keep their millimetres.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "fg/core/pipeline/units.hpp"
#include "fg/core/planner.hpp"
#include "synthetic_scene.hpp"

namespace {

using fg::PlanResult;
using fg::Pose;
using fg::SensorRole;
using fg::Status;
using fg::Vec3;
using fg::test::look_at;

const char* const kMm = "likely in millimetres";

TEST(UnitsMistake, NamesTheUnitsTheDepthsFit) {
  // The depths given, repeated to the sample's size (the same shares).
  const auto named = [](const std::vector<float>& d, float metres_per_unit = 1.f) {
    std::vector<float> sample;
    while (!d.empty() && sample.size() < fg::kUnitSamples) sample.insert(sample.end(), d.begin(), d.end());
    const char* m = fg::units_mistake(sample.data(), static_cast<uint32_t>(sample.size()), 0.3f, 1.5f, metres_per_unit);
    return std::string(m == nullptr ? "" : m);
  };
  EXPECT_NE(named({450.f, 800.f, 1200.f, 640.f}).find(kMm), std::string::npos);
  EXPECT_NE(named({45.f, 80.f, 120.f, 64.f}).find("likely in centimetres"), std::string::npos);
  EXPECT_NE(named({0.00045f, 0.0008f, 0.0012f}).find("1000 times too small"), std::string::npos);
  // Declared millimetres, given metres (read as mm: all under the range).
  EXPECT_NE(named({0.45f, 0.8f, 1.2f}, 0.001f).find("likely in metres"), std::string::npos);
  // Half in range read as mm is enough; fewer is not.
  EXPECT_NE(named({450.f, 800.f, 9000.f, 7000.f}).find(kMm), std::string::npos);
  EXPECT_EQ(named({450.f, 2.f, 3.f, 4.f}), "");
  // Beyond the range in metres, at depths a room has: no units to blame.
  EXPECT_EQ(named({2.f, 3.5f, 4.f, 6.f}), "");
  // Absurd whatever the units: every depth over 100 times the range.
  EXPECT_NE(named({2e6f, 5e6f}).find("100 times outside"), std::string::npos);
  EXPECT_EQ(named({}), "");
  EXPECT_EQ(fg::units_mistake(nullptr, 30, 0.3f, 1.5f, 1.f), nullptr);
  // Too few to say: a handful of stray points.
  const std::vector<float> few(fg::kUnitSamplesNeeded - 1, 800.f);
  EXPECT_EQ(fg::units_mistake(few.data(), static_cast<uint32_t>(few.size()), 0.3f, 1.5f, 1.f), nullptr);
}

// A box on a table as a head sensor sees it, in its optical frame, times `scale`.
struct SensorCloud {
  Pose pose = look_at(Vec3(-0.2f, -0.1f, 0.7f), Vec3(0.5f, 0.f, 0.05f));
  std::vector<float> xyz;
  explicit SensorCloud(float scale) {
    std::mt19937 rng(6);
    std::vector<Vec3> world;
    fg::test::add_table(world, rng, 0.004f, 0.475f, 0.525f, -0.035f, 0.035f);
    fg::test::add_box(world, rng, 0.5f, 0.f, 0.05f, 0.07f, 0.12f, 0.0025f);
    for (const Vec3& w : world) {
      const Vec3 p = pose.R.transpose() * (w - pose.t);
      xyz.insert(xyz.end(), {p.x() * scale, p.y() * scale, p.z() * scale});
    }
  }
  uint32_t n() const { return static_cast<uint32_t>(xyz.size() / 3); }
};

std::unique_ptr<fg::Planner> planner() {
  auto pl = std::make_unique<fg::Planner>();
  EXPECT_EQ(pl->configure(fg::PlannerConfig{}), Status::ok);
  return pl;
}

// A source of a cloud's points in pieces of 1000.
class Pieces final : public fg::PointSource {
 public:
  explicit Pieces(const std::vector<float>& xyz) : xyz_(xyz) {}
  bool next(fg::PointPiece& p) override {
    const uint32_t n = static_cast<uint32_t>(xyz_.size() / 3);
    const uint32_t count = n - at_ < 1000u ? n - at_ : 1000u;
    const auto* b = reinterpret_cast<const uint8_t*>(xyz_.data() + 3 * at_);
    p = fg::PointPiece{b, b + 4, b + 8, 12, count};
    at_ += count;
    return true;
  }

 private:
  const std::vector<float>& xyz_;
  uint32_t at_ = 0;
};

TEST(PlannerUnits, AMillimetreCloudIsRefusedNamingItsUnits) {
  const SensorCloud mm(1000.f);
  std::vector<float> x, y, z;
  for (uint32_t i = 0; i < mm.n(); ++i) {
    x.push_back(mm.xyz[3 * i]);
    y.push_back(mm.xyz[3 * i + 1]);
    z.push_back(mm.xyz[3 * i + 2]);
  }
  for (int how = 0; how < 3; ++how) {
    SCOPED_TRACE(how);
    auto pl = planner();
    Pieces src(mm.xyz);
    const Status s = how == 0   ? pl->add_points(SensorRole::head, mm.xyz.data(), mm.n(), 12, mm.pose)
                     : how == 1 ? pl->add_points_planar(SensorRole::head, x.data(), y.data(), z.data(), mm.n(), mm.pose)
                                : pl->add_point_source(SensorRole::head, src, mm.pose);
    EXPECT_EQ(s, Status::invalid_argument);
    EXPECT_NE(std::string(pl->last_message()).find(kMm), std::string::npos) << pl->last_message();
  }
  // Declared, it plans.
  auto pl = planner();
  ASSERT_EQ(pl->set_sensor_units(SensorRole::head, 0.001f), Status::ok);
  ASSERT_EQ(pl->add_points(SensorRole::head, mm.xyz.data(), mm.n(), 12, mm.pose), Status::ok);
  PlanResult r;
  EXPECT_EQ(pl->plan(r), Status::ok) << r.message;
  EXPECT_LT((r.grasp.position - Vec3(0.5f, 0.f, 0.06f)).norm(), 0.07f);
}

// At a power-of-two scale every product is exact: the plan is the metres' plan, bit for bit.
TEST(PlannerUnits, DeclaredUnitsPlanAsMetres) {
  const SensorCloud m(1.f), halves(2.f);
  auto a = planner(), b = planner();
  ASSERT_EQ(a->add_points(SensorRole::head, m.xyz.data(), m.n(), 12, m.pose), Status::ok);
  ASSERT_EQ(b->set_sensor_units(SensorRole::head, 0.5f), Status::ok);
  b->reset();  // the units stay
  EXPECT_EQ(b->sensor_units(SensorRole::head), 0.5f);
  ASSERT_EQ(b->add_points(SensorRole::head, halves.xyz.data(), halves.n(), 12, halves.pose), Status::ok);
  PlanResult ra, rb;
  ASSERT_EQ(a->plan(ra), Status::ok);
  ASSERT_EQ(b->plan(rb), Status::ok);
  EXPECT_EQ(std::memcmp(ra.grasp.position.data(), rb.grasp.position.data(), 12), 0);
  EXPECT_EQ(std::memcmp(ra.grasp.closing.data(), rb.grasp.closing.data(), 12), 0);
  EXPECT_EQ(ra.points.voxels, rb.points.voxels);
  EXPECT_EQ(ra.points.after_filter, rb.points.after_filter);
  EXPECT_EQ(std::memcmp(a->sight_map(SensorRole::head), b->sight_map(SensorRole::head),
                        sizeof(uint16_t) * fg::kSightBins * fg::kSightBins),
            0);
}

TEST(PlannerUnits, BadUnitsAreRefused) {
  auto pl = planner();
  EXPECT_EQ(pl->set_sensor_units(SensorRole::hand, 0.f), Status::invalid_argument);
  EXPECT_EQ(pl->set_sensor_units(SensorRole::hand, -0.001f), Status::invalid_argument);
  EXPECT_EQ(pl->set_sensor_units(SensorRole::hand, 1e4f), Status::invalid_argument);
  EXPECT_EQ(pl->set_sensor_units(SensorRole::hand, NAN), Status::non_finite);
  EXPECT_EQ(pl->set_sensor_units(static_cast<SensorRole>(7), 1.f), Status::invalid_sensor);
  EXPECT_EQ(pl->sensor_units(SensorRole::hand), 1.f);
}

// A cloud beyond the range in metres (a far wall): nothing to blame on units, the plan
// says there are no points.
TEST(PlannerUnits, AFarCloudIsNoUnitsMistake) {
  SensorCloud far(4.f);  // 2-4 m away
  auto pl = planner();
  ASSERT_EQ(pl->add_points(SensorRole::head, far.xyz.data(), far.n(), 12, far.pose), Status::ok);
  PlanResult r;
  EXPECT_EQ(pl->plan(r), Status::no_grasp);
  EXPECT_EQ(r.reason, fg::NoGraspReason::no_points);
}

// The sample spans the whole cloud: millimetre points after a long run of far ones (the
// first 40% of the cloud 4-6 m away, beyond the range in either unit) are still found;
// a sample of the first points alone would call the scale absurd instead.
TEST(PlannerUnits, TheSampleSpansTheCloud) {
  const SensorCloud mm(1000.f);
  std::vector<float> xyz;
  const uint32_t far = mm.n() * 2 / 3;
  for (uint32_t i = 0; i < far; ++i) xyz.insert(xyz.end(), {0.f, 0.f, 4000.f + static_cast<float>(i % 2000)});
  xyz.insert(xyz.end(), mm.xyz.begin(), mm.xyz.end());
  auto pl = planner();
  EXPECT_EQ(pl->add_points(SensorRole::head, xyz.data(), static_cast<uint32_t>(xyz.size() / 3), 12, mm.pose),
            Status::invalid_argument);
  EXPECT_NE(std::string(pl->last_message()).find(kMm), std::string::npos) << pl->last_message();
}

// Depth images carry their millimetres: a sensor's units do not apply to them.
TEST(PlannerUnits, DepthImagesKeepTheirMillimetres) {
  const fg::PinholeIntrinsics k{100.f, 100.f, 31.5f, 23.5f};
  std::vector<uint16_t> depth(64 * 48, 800);
  auto a = planner(), b = planner();
  const Pose pose = look_at(Vec3(0.5f, 0.f, 0.8f), Vec3(0.5f, 0.01f, 0.f));
  ASSERT_EQ(b->set_sensor_units(SensorRole::head, 0.001f), Status::ok);
  ASSERT_EQ(a->add_depth_image(SensorRole::head, depth.data(), 64, 48, k, pose), Status::ok);
  ASSERT_EQ(b->add_depth_image(SensorRole::head, depth.data(), 64, 48, k, pose), Status::ok);
  PlanResult ra, rb;
  (void)a->plan(ra);
  (void)b->plan(rb);
  EXPECT_EQ(ra.points.after_filter, 64u * 48u);
  EXPECT_EQ(rb.points.after_filter, ra.points.after_filter);
  EXPECT_EQ(rb.points.voxels, ra.points.voxels);
}

}  // namespace
