// End to end on real depth captures (shared/data/clouds/mosd, labelled by their
// authors): the shipped example manifests, and scenes built here the same way for
// other objects (table plane -> z = 0, camera looking along +x, object N's centroid at
// the workspace centre). Every assertion is checked against the capture's labels:
// the grasp lies on the labelled target, its width is within the opening, and the
// fingers stay above the labelled table (plane fitted here with Eigen). Last, one
// capture of another kind (PCL's floor scene, its carton's own cloud as the truth).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "fg/core/planner.hpp"
#include "io/pcd.hpp"
#include "io/scene.hpp"

namespace {
const std::string kShared = FG_SHARED_DIR;

struct Capture {
  fg::host::PointCloud cloud;  // optical frame, with labels
};

const Capture& capture(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Capture>> cache;
  auto& c = cache[name];
  if (!c) {
    c = std::make_unique<Capture>();
    const auto r = fg::host::read_pcd(kShared + "/data/clouds/mosd/" + name + ".pcd", c->cloud);
    EXPECT_TRUE(r.ok) << r.error;
    EXPECT_EQ(c->cloud.labels.size(), c->cloud.size());
  }
  return *c;
}

bool is_table(uint32_t label) { return label >= 1 && label <= 9; }
bool is_object(uint32_t label, int n) { return static_cast<int>(label / 10) == n; }

// world_T_sensor as the shipped manifests define it (shared/data/README.md).
fg::Pose scene_pose(const Capture& cap, int object) {
  // Least-squares table plane from the label-1..9 points (Eigen, independent of core).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), obj = Eigen::Vector3d::Zero();
  size_t n = 0, m = 0;
  const auto& xyz = cap.cloud.xyz;
  for (size_t i = 0; i < cap.cloud.size(); ++i) {
    const Eigen::Vector3d p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!p.allFinite()) continue;
    if (is_table(cap.cloud.labels[i])) mean += p, ++n;
    if (is_object(cap.cloud.labels[i], object)) obj += p, ++m;
  }
  mean /= static_cast<double>(n);
  obj /= static_cast<double>(m);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < cap.cloud.size(); ++i) {
    const Eigen::Vector3d p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!p.allFinite() || !is_table(cap.cloud.labels[i])) continue;
    C += (p - mean) * (p - mean).transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  Eigen::Vector3d up = es.eigenvectors().col(0);
  if (up.dot(-mean) < 0) up = -up;  // towards the camera
  // World axes in the sensor frame: z = up, x = the view direction along the table.
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ() - up * up.z();
  x.normalize();
  const Eigen::Vector3d y = up.cross(x);
  Eigen::Matrix3d R_ws;  // rows: world axes expressed in the sensor frame
  R_ws.row(0) = x;
  R_ws.row(1) = y;
  R_ws.row(2) = up;
  // Table at z = 0 and the object's centroid at (0.5, 0).
  const Eigen::Vector3d o = R_ws * obj;
  const double h0 = up.dot(mean);
  const Eigen::Vector3d t(0.5 - o.x(), -o.y(), -h0);
  fg::Pose pose;
  pose.R = R_ws.cast<float>();
  pose.t = t.cast<float>();
  return pose;
}

// The scene of `pose` as built (variant 0), turned by +-20 deg about the vertical
// through the workspace centre (1, 2), or shifted about 5 cm along the table (3, 4):
// held-out manifests will not put the target exactly where scene_pose does.
constexpr int kSceneVariants = 5;
fg::Pose turned_or_shifted(fg::Pose pose, int variant) {
  const float yaw = variant == 1 ? 0.35f : variant == 2 ? -0.35f : 0.f;
  const fg::Vec3 shift = variant == 3   ? fg::Vec3(0.04f, 0.03f, 0.f)
                         : variant == 4 ? fg::Vec3(-0.03f, -0.04f, 0.f)
                                        : fg::Vec3::Zero();
  const Eigen::Matrix3f turn = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  const fg::Vec3 centre(0.5f, 0.f, 0.f);
  pose.R = turn * pose.R;
  pose.t = turn * (pose.t - centre) + centre + shift;
  return pose;
}

// A world point between the grasp's pads (5 mm of slack along the closing direction).
bool between_pads(const fg::Grasp& g, const fg::Vec3& w) {
  const fg::Vec3 d = w - g.position;
  return std::fabs(d.dot(g.closing)) <= 0.5f * g.width + 0.005f &&
         std::fabs(d.dot(g.approach.cross(g.closing))) <= 0.011f && std::fabs(d.dot(g.approach)) <= 0.02f;
}

// The lowest world z of the two fingers' corners, closed (at the grasp's width) and open.
double lowest_finger_z(const fg::Grasp& g, float opening) {
  const fg::Vec3 Y = g.approach.cross(g.closing);
  const float half_fd = 0.02f, t = 0.01f, hy = 0.011f;
  double lowest = 1e9;
  for (float half_x : {0.5f * g.width, 0.5f * opening})
    for (int k = 0; k < 16; ++k) {
      const float sx = (k & 1) ? 1.f : -1.f;
      const float x = sx * (half_x + ((k & 8) ? t : 0.f));
      const fg::Vec3 c =
          g.position + g.closing * x + Y * ((k & 2) ? hy : -hy) + g.approach * ((k & 4) ? half_fd : -half_fd);
      lowest = std::min(lowest, static_cast<double>(c.z()));
    }
  return lowest;
}

struct Outcome {
  fg::Status status;
  fg::PlanResult result;
  int target_points_between_pads = 0;
  int other_points_between_pads = 0;
  std::map<int, int> points_between_pads;  // per labelled object (label / 10)
  int table_points_between_pads = 0;
  double min_finger_height = 1e9;  // above the labelled table plane
};

Outcome plan_on(const Capture& cap, const fg::Pose& pose, int object, float opening) {
  static auto planner = std::make_unique<fg::Planner>();
  fg::PlannerConfig cfg;
  cfg.gripper.max_opening_m = opening;
  EXPECT_EQ(planner->configure(cfg), fg::Status::ok);
  EXPECT_EQ(planner->add_points(fg::SensorRole::head, cap.cloud.xyz.data(), static_cast<uint32_t>(cap.cloud.size()), 12,
                                pose),
            fg::Status::ok);
  Outcome o;
  o.status = planner->plan(o.result);
  if (o.status != fg::Status::ok) return o;
  const fg::Grasp& g = o.result.grasp;
  const auto& xyz = cap.cloud.xyz;
  // Table plane in world from the labels (points transformed by the pose).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (size_t i = 0; i < cap.cloud.size(); ++i) {
    const fg::Vec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!p.allFinite()) continue;
    const fg::Vec3 w = pose.apply(p);
    if (is_table(cap.cloud.labels[i])) mean += w.cast<double>(), ++n;
    if (between_pads(g, w)) {
      const uint32_t label = cap.cloud.labels[i];
      if (is_object(label, object))
        ++o.target_points_between_pads;
      else
        ++o.other_points_between_pads;
      if (label >= 20) ++o.points_between_pads[static_cast<int>(label / 10)];
      if (is_table(label)) ++o.table_points_between_pads;
    }
  }
  const double table_z = mean.z() / static_cast<double>(n);
  o.min_finger_height = lowest_finger_z(g, opening) - table_z;
  return o;
}

void expect_grasp_on_target(const std::string& cap_name, int object, float opening) {
  SCOPED_TRACE(cap_name + " object " + std::to_string(object));
  const Capture& cap = capture(cap_name);
  const Outcome o = plan_on(cap, scene_pose(cap, object), object, opening);
  ASSERT_EQ(o.status, fg::Status::ok) << o.result.message << " (" << fg::to_string(o.result.reason) << ")";
  EXPECT_GT(o.target_points_between_pads, 10) << "the pads do not hold the labelled target";
  EXPECT_GT(o.target_points_between_pads, 4 * o.other_points_between_pads)
      << "the pads hold more of another object than of the target";
  EXPECT_GT(o.result.grasp.width, 0.005f);
  EXPECT_LE(o.result.grasp.width, opening);
  EXPECT_GT(o.min_finger_height, -0.005) << "a finger goes through the table";
}
}  // namespace

// The manifests that ship in shared/data/scenes (2F-140 class, 0.14 m opening).
TEST(RealCaptures, ShippedManifestsGraspTheirTarget) {
  struct Case {
    const char* scene;
    const char* capture;
    int object;
  } cases[] = {{"learn42-obj3", "learn42", 3}, {"learn3-obj3", "learn3", 3}};
  for (const Case& c : cases) {
    fg::host::Scene scene;
    const auto r = fg::host::read_scene(kShared + "/data/scenes/" + c.scene + "/scene.json", scene);
    ASSERT_TRUE(r.ok) << r.error;
    ASSERT_EQ(scene.sensors.size(), 1u);
    const fg::Pose pose = fg::host::to_pose(*scene.sensors[0].pose);
    // The pose built here from the labels is the manifest's (a check of this test's oracle).
    const Capture& cap = capture(c.capture);
    const fg::Pose mine = scene_pose(cap, c.object);
    EXPECT_LT((mine.t - pose.t).norm(), 0.01f) << c.scene;
    EXPECT_LT((mine.R - pose.R).cwiseAbs().maxCoeff(), 0.01f) << c.scene;
    SCOPED_TRACE(c.scene);
    const Outcome o = plan_on(cap, pose, c.object, static_cast<float>(scene.gripper.max_opening));
    ASSERT_EQ(o.status, fg::Status::ok) << o.result.message;
    EXPECT_GT(o.target_points_between_pads, 10);
    EXPECT_GT(o.target_points_between_pads, 4 * o.other_points_between_pads);
    EXPECT_LE(o.result.grasp.width, scene.gripper.max_opening);
    EXPECT_GT(o.min_finger_height, -0.005);
  }
}

// Objects of the other captures that fit a 0.14 m opening.
TEST(RealCaptures, ChipsCanStandingUpright) { expect_grasp_on_target("learn44", 3, 0.14f); }
TEST(RealCaptures, MugBesideTheCan) { expect_grasp_on_target("learn44", 4, 0.14f); }
TEST(RealCaptures, CanWithRedLid) { expect_grasp_on_target("test36", 3, 0.14f); }
TEST(RealCaptures, DarkTallCan) { expect_grasp_on_target("test36", 4, 0.14f); }
TEST(RealCaptures, DarkCylindricalCan) { expect_grasp_on_target("test31", 3, 0.14f); }
// The labelled object's points in the scene's world (z: height above the labelled
// table plane).
std::vector<fg::Vec3> object_points_in_world(const Capture& cap, int object) {
  const fg::Pose pose = scene_pose(cap, object);  // world z is the table's normal
  const auto& xyz = cap.cloud.xyz;
  std::vector<fg::Vec3> pts;
  for (size_t i = 0; i < cap.cloud.size(); ++i) {
    const fg::Vec3 p(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (p.allFinite() && is_object(cap.cloud.labels[i], object)) pts.push_back(pose.apply(p));
  }
  return pts;
}

// The labelled object's smallest width over horizontal closing directions (its points
// projected on the labelled table plane, brute force over 0.25 deg steps). What the
// sensor saw is part of the object, so the object is at least this wide.
double min_horizontal_width(const Capture& cap, int object) {
  const std::vector<fg::Vec3> pts = object_points_in_world(cap, object);
  double best = 1e9;
  for (int k = 0; k < 720; ++k) {
    const double a = k * 3.14159265358979 / 720.0;
    const double dx = std::cos(a), dy = std::sin(a);
    double lo = 1e9, hi = -1e9;
    for (const fg::Vec3& q : pts) {
      const double t = dx * q.x() + dy * q.y();
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    best = std::min(best, hi - lo);
  }
  return pts.empty() ? 0.0 : best;
}

// Objects wider than the opening in every horizontal direction, by their labels: no
// grasp closes across them, so the answer is no_grasp (issue 3's rule for objects that
// fit nowhere). learn33: a flat round cookie tin, a white bowl, and the open pot whose
// shipped manifest is shared/data/scenes/learn33-obj4 (its near rim and the inside of its
// far wall are seen; 154 mm across at least).
TEST(RealCaptures, ObjectsWiderThanTheOpeningGetNoGrasp) {
  const float opening = 0.14f;
  for (int object : {2, 3, 4}) {
    SCOPED_TRACE("learn33 object " + std::to_string(object));
    const Capture& cap = capture("learn33");
    const double width = min_horizontal_width(cap, object);
    EXPECT_GT(width, opening + 0.01);
    EXPECT_LT(width, 0.3);  // one object, not the table
    const Outcome o = plan_on(cap, scene_pose(cap, object), object, opening);
    EXPECT_EQ(o.status, fg::Status::no_grasp)
        << "object " << width << " m wide, a grasp of width " << o.result.grasp.width;
  }
}
// A small box behind a larger one: its top and the upper half of its front face are
// seen. Most candidates approach from the side and meet the large box or the unseen
// space behind the small one. The grasp straight down across the narrow side is the
// 69th candidate checked (of 136 found): it needs FG_MAX_CHECKED_CANDIDATES = 128 (with
// 64 the answer was no_grasp, `collision`).
TEST(RealCaptures, SmallBoxBehindTheLargeOne) { expect_grasp_on_target("learn8", 3, 0.14f); }
TEST(RealCaptures, MugOnTheTable) { expect_grasp_on_target("learn33", 5, 0.14f); }

// The same with the default 2F-85 class gripper (0.085 m) where the object fits it.
TEST(RealCaptures, CansFitTheSmallGripper) { expect_grasp_on_target("learn44", 3, 0.085f); }

// The diameter of an upright cylinder from the labelled points of its side between two
// heights above the table: the least-squares circle through their (x, y) (Kasa's
// linear fit x^2 + y^2 = a x + b y + c, solved by Eigen's QR). The sensor sees an arc
// of the side, which a circle fit recovers where the arc's chord would not.
double arc_diameter(const Capture& cap, int object, double z_lo, double z_hi) {
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> rhs;
  for (const fg::Vec3& w : object_points_in_world(cap, object)) {
    if (w.z() < z_lo || w.z() >= z_hi) continue;
    rows.emplace_back(w.x(), w.y(), 1.0);
    rhs.push_back(static_cast<double>(w.x()) * w.x() + static_cast<double>(w.y()) * w.y());
  }
  if (rows.size() < 10) return 0.0;
  Eigen::MatrixXd a(rows.size(), 3);
  Eigen::VectorXd b(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    a.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
    b(static_cast<Eigen::Index>(i)) = rhs[i];
  }
  const Eigen::Vector3d c = a.colPivHouseholderQr().solve(b);
  const double cx = 0.5 * c(0), cy = 0.5 * c(1);
  return 2.0 * std::sqrt(c(2) + cx * cx + cy * cy);
}

// The can with the red lid is about 10 cm across: too wide for the 0.085 m opening in
// every direction, so no_grasp (a chord grasp across its near side would hold it by
// contacts some 50 deg outside the friction cone). The fit's own check: the chips can
// (YCB's is 78 mm across) comes out between 7 and 9 cm.
TEST(RealCaptures, CanWithRedLidIsTooWideForTheSmallGripper) {
  const float opening = 0.085f;
  EXPECT_GT(arc_diameter(capture("learn44"), 3, 0.0, 0.16), 0.07);
  EXPECT_LT(arc_diameter(capture("learn44"), 3, 0.0, 0.16), 0.09);
  const double d = arc_diameter(capture("test36"), 3, 0.0, 0.08);
  EXPECT_GT(d, opening + 0.01);
  EXPECT_LT(d, 0.15);
  const Capture& cap = capture("test36");
  const Outcome o = plan_on(cap, scene_pose(cap, 3), 3, opening);
  EXPECT_EQ(o.status, fg::Status::no_grasp) << "a can " << d << " m across, a grasp of width " << o.result.grasp.width;
}

// Every labelled object of every capture, with both grippers and with the scene turned
// and shifted about the workspace centre (held-out manifests will not put the target
// exactly where scene_pose does). Whatever the planner answers must be true of the
// labels: a grasp holds a labelled object between its pads (the target, or what the
// dataset's description says stands on it), not the table; its width is within the
// opening; no finger goes through the table; a no_grasp names its reason, and when
// candidates were refused, the reason is the check that refused most of them.
TEST(RealCaptures, EveryLabelledObjectUnderTurnedAndShiftedScenes) {
  // shared/data/README.md: learn42 "a mug standing on a round cookie tin (stacked)",
  // test31 "a chips can standing on the tin": grasping the object on top is grasping
  // the pile the target belongs to.
  const auto stands_on = [](const std::string& cap, int top, int base) {
    return (cap == "learn42" && base == 2 && top == 3) || (cap == "test31" && base == 2 && top == 4);
  };
  int grasps = 0, refusals = 0;
  for (const char* name : {"learn3", "learn8", "learn33", "learn42", "learn44", "test31", "test36"}) {
    const Capture& cap = capture(name);
    std::map<int, size_t> objects;
    for (uint32_t l : cap.cloud.labels)
      if (l >= 20) ++objects[static_cast<int>(l / 10)];
    ASSERT_GE(objects.size(), 2u) << name;
    for (const auto& entry : objects) {
      const int object = entry.first;
      for (const float opening : {0.085f, 0.14f})
        for (int variant = 0; variant < kSceneVariants; ++variant) {
          SCOPED_TRACE(std::string(name) + " object " + std::to_string(object) + " opening " + std::to_string(opening) +
                       " variant " + std::to_string(variant));
          const fg::Pose pose = turned_or_shifted(scene_pose(cap, object), variant);
          const Outcome o = plan_on(cap, pose, object, opening);
          if (o.status == fg::Status::no_grasp) {
            ++refusals;
            const fg::RejectCounts& rj = o.result.rejected;
            EXPECT_NE(o.result.reason, fg::NoGraspReason::none);
            EXPECT_STRNE(o.result.message, "");
            if (o.result.reason == fg::NoGraspReason::occluded) {
              EXPECT_GT(rj.occluded, rj.collision + rj.table);
              EXPECT_GT(rj.occluded, rj.friction);
              // Which sensor would have to look where.
              EXPECT_TRUE(o.result.look.valid);
            }
            if (o.result.reason == fg::NoGraspReason::collision) {
              EXPECT_GE(rj.collision + rj.table, rj.occluded) << "the refusals were mostly for occlusion";
            }
            continue;
          }
          ASSERT_EQ(o.status, fg::Status::ok) << o.result.message;
          ++grasps;
          int held = 0, most = 0;
          for (const auto& [label_object, count] : o.points_between_pads)
            if (count > most) most = count, held = label_object;
          EXPECT_TRUE(held == object || stands_on(name, held, object))
              << "the pads hold object " << held << " (" << most << " points)";
          EXPECT_GT(most, 10);
          EXPECT_LT(o.table_points_between_pads, std::max(5, most / 4)) << "the pads hold the table";
          EXPECT_GT(o.result.grasp.width, 0.f);
          EXPECT_LE(o.result.grasp.width, opening);
          EXPECT_GT(o.min_finger_height, -0.005) << "a finger goes through the table";
        }
    }
  }
  // Both answers occur (the sweep is no vacuous pass): 20 labelled objects x 10 scenes.
  std::printf("%d grasps, %d no_grasp answers\n", grasps, refusals);
  EXPECT_GT(grasps, 80);
  EXPECT_GT(refusals, 50);
}

// A second kind of capture: PCL's test scene of three household objects on a carpeted
// floor (a Kinect-type camera, shared/data/clouds/pcl), with the milk carton's own
// cloud as its ground truth (milk_color.pcd: every point of the carton, the same
// points to 1e-4 m). The floor plane is the one shared/data/README.md gives; the
// carton's centroid goes to the workspace centre, then the scene is turned and shifted
// as above. With the 0.14 m gripper the carton (10 x 15 cm seen, 25 cm tall) fits
// across its narrow side: every answer is a grasp whose pads hold carton points. With
// the 0.085 m one only its top's seam fits: a grasp there, or no_grasp with a reason.
TEST(RealCaptures, MilkCartonOnTheFloor) {
  fg::host::PointCloud scene, carton;
  ASSERT_TRUE(fg::host::read_pcd(kShared + "/data/clouds/pcl/milk_cartoon_all_small_clorox.pcd", scene).ok);
  ASSERT_TRUE(fg::host::read_pcd(kShared + "/data/clouds/pcl/milk_color.pcd", carton).ok);
  ASSERT_GT(carton.size(), 10000u);
  const Eigen::Vector3d up = Eigen::Vector3d(0.004, -0.820, -0.573).normalized();
  const double floor_d = 0.466;  // n.p + d is a point's height above the floor
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < carton.size(); ++i)
    centroid += Eigen::Vector3d(carton.xyz[3 * i], carton.xyz[3 * i + 1], carton.xyz[3 * i + 2]);
  centroid /= static_cast<double>(carton.size());
  Eigen::Vector3d x = Eigen::Vector3d::UnitZ() - up * up.z();
  x.normalize();
  Eigen::Matrix3d R_ws;
  R_ws.row(0) = x;
  R_ws.row(1) = up.cross(x);
  R_ws.row(2) = up;
  const Eigen::Vector3d o = R_ws * centroid;
  const auto is_carton = [&carton](const fg::Vec3& q) {
    for (size_t j = 0; j < carton.size(); ++j)
      if (std::fabs(carton.xyz[3 * j] - q.x()) < 1e-4f && std::fabs(carton.xyz[3 * j + 1] - q.y()) < 1e-4f &&
          std::fabs(carton.xyz[3 * j + 2] - q.z()) < 1e-4f)
        return true;
    return false;
  };
  static auto planner = std::make_unique<fg::Planner>();
  for (const float opening : {0.085f, 0.14f})
    for (int variant = 0; variant < kSceneVariants; ++variant) {
      SCOPED_TRACE("opening " + std::to_string(opening) + " variant " + std::to_string(variant));
      fg::Pose centred;
      centred.R = R_ws.cast<float>();
      centred.t = Eigen::Vector3d(0.5 - o.x(), -o.y(), floor_d).cast<float>();  // floor at z = 0
      const fg::Pose pose = turned_or_shifted(centred, variant);
      fg::PlannerConfig cfg;
      cfg.gripper.max_opening_m = opening;
      ASSERT_EQ(planner->configure(cfg), fg::Status::ok);
      ASSERT_EQ(
          planner->add_points(fg::SensorRole::head, scene.xyz.data(), static_cast<uint32_t>(scene.size()), 12, pose),
          fg::Status::ok);
      fg::PlanResult res;
      const fg::Status st = planner->plan(res);
      if (opening < 0.1f && st == fg::Status::no_grasp) {
        EXPECT_NE(res.reason, fg::NoGraspReason::none);
        continue;
      }
      ASSERT_EQ(st, fg::Status::ok) << res.message;
      const fg::Grasp& g = res.grasp;
      int on_carton = 0, other = 0;
      for (size_t i = 0; i < scene.size(); ++i) {
        const fg::Vec3 q(scene.xyz[3 * i], scene.xyz[3 * i + 1], scene.xyz[3 * i + 2]);
        if (q.allFinite() && between_pads(g, pose.apply(q))) ++(is_carton(q) ? on_carton : other);
      }
      EXPECT_GT(on_carton, 10) << "the pads do not hold the carton";
      EXPECT_GT(on_carton, 4 * other) << "the pads hold more of something else";
      EXPECT_GT(g.width, 0.f);
      EXPECT_LE(g.width, opening);
      // The fingers' lowest corner, open and closed, above the floor (z = 0).
      EXPECT_GT(lowest_finger_z(g, opening), -0.005) << "a finger goes through the floor";
    }
}

// Every object on the table (Planner::plan_object after plan(), `--objects all`) on
// every labelled capture, with both grippers, as built and turned. Each listed object is
// identified by its voxels' labels (the labelled object most of its points belong to);
// a grasp planned for it must hold that labelled object between its pads (or the one
// it stands on or under, where the two touch and form one cluster), not another, not
// the table, within the opening and above the table. Every labelled object that fits
// the gripper across some horizontal direction, and stands apart, gets a grasp lying on
// it. Two stacked objects touch: they are one cluster, one object of the list, and
// its plan holds one of them (or neither: the mug on the tin with the small gripper).
TEST(RealCaptures, EveryObjectOnTheTable) {
  const auto stacked = [](const std::string& cap, int a, int b) {
    const auto on = [&](int top, int base) {
      return (cap == "learn42" && base == 2 && top == 3) || (cap == "test31" && base == 2 && top == 4);
    };
    return on(a, b) || on(b, a);
  };
  static auto planner = std::make_unique<fg::Planner>();
  int fitting = 0, fitting_grasped = 0, grasps = 0, objects_listed = 0;
  std::string missed;
  for (const char* name : {"learn3", "learn8", "learn33", "learn42", "learn44", "test31", "test36"}) {
    const Capture& cap = capture(name);
    std::map<int, size_t> labelled;
    for (uint32_t l : cap.cloud.labels)
      if (l >= 20) ++labelled[static_cast<int>(l / 10)];
    for (const float opening : {0.085f, 0.14f})
      for (int variant : {0, 1}) {
        SCOPED_TRACE(std::string(name) + " opening " + std::to_string(opening) + " variant " + std::to_string(variant));
        const fg::Pose pose = turned_or_shifted(scene_pose(cap, 2), variant);
        fg::PlannerConfig cfg;
        cfg.gripper.max_opening_m = opening;
        ASSERT_EQ(planner->configure(cfg), fg::Status::ok);
        ASSERT_EQ(planner->add_points(fg::SensorRole::head, cap.cloud.xyz.data(),
                                      static_cast<uint32_t>(cap.cloud.size()), 12, pose),
                  fg::Status::ok);
        fg::PlanResult res;
        const fg::Status st = planner->plan(res);
        ASSERT_TRUE(st == fg::Status::ok || st == fg::Status::no_grasp) << res.message;
        const uint32_t n = planner->object_count();
        size_t apart = labelled.size();  // stacked pairs make one cluster each
        for (const auto& a : labelled)
          for (const auto& b : labelled) apart -= a.first < b.first && stacked(name, a.first, b.first) ? 1u : 0u;
        EXPECT_GE(n, apart) << "fewer objects than labelled ones standing apart";
        EXPECT_EQ(planner->objects_dropped(), 0u);
        objects_listed += static_cast<int>(n);
        std::map<int, bool> grasped;  // labelled object -> a grasp lies on it
        const float leaf = cfg.voxel_leaf_m;
        for (uint32_t k = 0; k < n; ++k) {
          fg::PlanResult r;
          const fg::Status sk = planner->plan_object(k, r);
          ASSERT_TRUE(sk == fg::Status::ok || sk == fg::Status::no_grasp) << r.message;
          // The object's identity: the labels of the cloud points in its voxels' cells.
          std::set<std::tuple<int, int, int>> cells;
          const auto cell_of = [leaf](const fg::Vec3& w) {
            return std::make_tuple(static_cast<int>(std::floor(w.x() / leaf)),
                                   static_cast<int>(std::floor(w.y() / leaf)),
                                   static_cast<int>(std::floor(w.z() / leaf)));
          };
          const fg::PointSpan& pts = planner->object_points();
          for (uint32_t i = 0; i < pts.size(); ++i) cells.insert(cell_of(pts[i]));
          EXPECT_EQ(pts.size(), planner->object(k).voxels);
          std::map<int, int> in_cells, between;
          int table_between = 0;
          for (size_t i = 0; i < cap.cloud.size(); ++i) {
            const fg::Vec3 p(cap.cloud.xyz[3 * i], cap.cloud.xyz[3 * i + 1], cap.cloud.xyz[3 * i + 2]);
            if (!p.allFinite()) continue;
            const fg::Vec3 w = pose.apply(p);
            const uint32_t label = cap.cloud.labels[i];
            if (label >= 20 && cells.count(cell_of(w)) != 0) ++in_cells[static_cast<int>(label / 10)];
            if (sk == fg::Status::ok && between_pads(r.grasp, w)) {
              if (label >= 20) ++between[static_cast<int>(label / 10)];
              if (is_table(label)) ++table_between;
            }
          }
          int identity = 0, most = 0;
          for (const auto& [obj, count] : in_cells)
            if (count > most) most = count, identity = obj;
          if (sk != fg::Status::ok) continue;
          ++grasps;
          int held = 0, held_points = 0;
          for (const auto& [obj, count] : between)
            if (count > held_points) held_points = count, held = obj;
          EXPECT_GT(held_points, 10) << "object " << k << ": its grasp holds no labelled object";
          EXPECT_TRUE(held == identity || stacked(name, held, identity))
              << "object " << k << " (labelled " << identity << ") has a grasp on labelled object " << held;
          EXPECT_LT(table_between, std::max(5, held_points / 4)) << "object " << k << ": the pads hold the table";
          EXPECT_LE(r.grasp.width, opening);
          EXPECT_GT(lowest_finger_z(r.grasp, opening), -0.005) << "a finger goes through the table";
          grasped[held] = true;
        }
        for (const auto& entry : labelled) {
          if (min_horizontal_width(cap, entry.first) > opening - 0.005) continue;
          bool is_stacked = false;
          for (const auto& other : labelled) is_stacked = is_stacked || stacked(name, entry.first, other.first);
          if (is_stacked) continue;
          ++fitting;
          if (grasped[entry.first]) {
            ++fitting_grasped;
          } else {
            missed += std::string(" ") + name + "/" + std::to_string(entry.first) + "@" +
                      std::to_string(static_cast<int>(opening * 1000)) + "v" + std::to_string(variant);
          }
        }
      }
  }
  std::printf("%d objects listed, %d grasps; %d of %d fitting labelled objects grasped; missed:%s\n", objects_listed,
              grasps, fitting_grasped, fitting, missed.c_str());
  EXPECT_GT(fitting, 20);
  EXPECT_EQ(fitting_grasped, fitting);
}
