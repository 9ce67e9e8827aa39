#include "plan/plan_report.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "fg/core/constants.hpp"

namespace fg::host {
namespace {
using nlohmann::json;

// A number, or null where it is not measured (NaN): JSON has no NaN, and the Python
// module's dict must be the program's report.
json finite_or_null(float v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

//! The report of a grasp: its pose and figures, and every check it passed with its
//! margin in the check's unit (null where the check measures none or does not apply;
//! the robot's only with its checks on).
json grasp_entry(const Grasp& g, const CheckMargins& margins, const PlannerConfig& cfg,
                 const robot::GraspCheckConfig& check_cfg) {
  json e{{"position", vec(g.position)},
         {"approach", vec(g.approach)},
         {"closing", vec(g.closing)},
         {"width", g.width},
         {"beta", g.beta},
         {"dz", g.dz},
         {"viewpoint", g.viewpoint},
         {"family", to_string(g.family)},
         {"pregrasp", vec(g.pregrasp)}};
  json checks = json::object();
  for (uint32_t k = 0; k < kCheckCount; ++k) {
    const CheckId id = static_cast<CheckId>(k);
    if (!cfg.executability_checks || (id == CheckId::robot_reach && !check_cfg.check_reach)) continue;
    const float m = margins[id];
    checks[to_string(id)] = json{{"margin", finite_or_null(m)}, {"unit", margin_unit(id)}};
  }
  e["checks"] = checks;
  return e;
}

//! The grasp, and the arm's joints when the robot's reach was checked.
void report_grasp(json& j, const PlanResult& res, const PlannerConfig& cfg, const robot::GraspCheckConfig& check_cfg,
                  const robot::Ur5GraspCheck& check) {
  j["grasp"] = grasp_entry(res.grasp, res.margins, cfg, check_cfg);
  if (check_cfg.check_reach && check.has_motion()) {
    const robot::GraspMotion& m = check.motion();
    const auto q = [](const double* v) { return json(std::vector<double>(v, v + 6)); };
    j["joints"] = json{{"pregrasp", q(m.pregrasp)}, {"grasp", q(m.grasp)}, {"lift", q(m.lift)}};
  }
}

//! The points, the crop box, the stages' times and the search's counts.
void report_figures(json& j, const PlanResult& res) {
  j["points"] = json{{"input", res.points.input},
                     {"after_filter", res.points.after_filter},
                     {"voxels", res.points.voxels},
                     {"plane", res.points.plane},
                     {"object", res.points.object}};
  // The crop box the grid was built in: the configured one, or the smaller one about
  // the workspace centre a cloud too large for the voxel grid left (docs/method.md A).
  j["crop"] = json{{"min", json::array({res.crop.min_x, res.crop.min_y})},
                   {"max", json::array({res.crop.max_x, res.crop.max_y})},
                   {"shrinks", res.crop.shrinks},
                   {"points_dropped", res.crop.points_dropped}};
  json timing = json::object();
  timing["total"] = res.stage_us[static_cast<int>(Stage::total)];
  for (int s = 0; s < static_cast<int>(Stage::total); ++s) timing[to_string(static_cast<Stage>(s))] = res.stage_us[s];
  // With two sensors: how the hand was registered to the head (docs/method.md A.4b).
  const RegistrationResult& reg = res.registration;
  if (reg.outcome != RegistrationOutcome::not_run) {
    const Pose& c = reg.correction;
    json rows = json::array();
    for (int r = 0; r < 3; ++r) rows.push_back(json::array({c.R(r, 0), c.R(r, 1), c.R(r, 2)}));
    j["registration"] = json{{"outcome", to_string(reg.outcome)},
                             {"translation_mm", reg.translation_mm},
                             {"rotation_deg", reg.rotation_deg},
                             {"residual_before_mm", reg.residual_before_mm},
                             {"residual_mm", reg.residual_mm},
                             {"overlap", reg.overlap},
                             {"pairs", reg.pairs},
                             {"iterations", reg.iterations},
                             {"see_through", reg.see_through},
                             {"compared", reg.compared},
                             {"head_tilt_deg", finite_or_null(reg.head_tilt_deg)},
                             {"hand_tilt_deg", finite_or_null(reg.hand_tilt_deg)},
                             {"left_out", reg.outcome == RegistrationOutcome::sensor_disagreement
                                              ? json(reg.left_out == SensorRole::head ? "head" : "hand")
                                              : json(nullptr)},
                             {"correction", json{{"R", rows}, {"t", json::array({c.t.x(), c.t.y(), c.t.z()})}}}};
    timing["registration"] = reg.us;
  }
  j["timing_us"] = timing;
  j["search"] = json{{"viewpoints", res.viewpoints},
                     {"candidates", res.candidates},
                     {"rejected",
                      {{"table", res.rejected.table},
                       {"collision", res.rejected.collision},
                       {"unreachable", res.rejected.unreachable},
                       {"friction", res.rejected.friction},
                       {"occluded", res.rejected.occluded}}}};
  json by_check = json::object();
  for (uint32_t k = 0; k < kCheckCount; ++k)
    by_check[to_string(static_cast<CheckId>(k))] = res.rejected_by_check.by_check[k];
  j["search"]["rejected_by_check"] = by_check;
}

}  // namespace

void set_up_robot_check(robot::Ur5GraspCheck& check, const PlannerConfig& cfg, const double* current_joints,
                        robot::GraspCheckConfig& check_cfg) {
  check_cfg.tool.gripper = cfg.gripper;
  check_cfg.check_reach = current_joints != nullptr;
  check.configure(check_cfg);
  if (current_joints != nullptr) check.set_current_joints(current_joints);
}

json plan_report(const Planner& planner, const PlanResult& res, Status st, const PlannerConfig& cfg,
                 const robot::GraspCheckConfig& check_cfg, const robot::Ur5GraspCheck& check) {
  json j;
  if (st == Status::ok) {
    j["status"] = "ok";
    report_grasp(j, res, cfg, check_cfg, check);
  } else if (st == Status::no_grasp) {
    j["status"] = "no_grasp";
    j["reason"] = to_string(res.reason);
    j["message"] = res.message;
    if (res.look.valid)
      j["look"] = json{{"sensor", res.look.sensor == SensorRole::head ? "head" : "hand"},
                       {"at", vec(res.look.at)},
                       {"from", vec(res.look.from)}};
  } else {
    j["status"] = "internal_error";
    j["error"] = res.message;
  }
  report_figures(j, res);
  if (planner.plane_found()) j["support_plane"] = json{{"normal", vec(planner.plane().n)}, {"d", planner.plane().d}};
  return j;
}

json ranked_grasps_report(const PlanResult& best, const RankedGrasp* more, uint32_t n_more, const PlannerConfig& cfg,
                          const robot::GraspCheckConfig& check_cfg) {
  json list = json::array();
  const float cone_deg = static_cast<float>(std::atan(static_cast<double>(cfg.friction_mu)) * 180.0 / kPi);
  for (uint32_t k = 0; k <= n_more; ++k) {
    const Grasp& g = k == 0 ? best.grasp : more[k - 1].grasp;
    const CheckMargins& m = k == 0 ? best.margins : more[k - 1].margins;
    json e = grasp_entry(g, m, cfg, check_cfg);
    e["rank"] = k;
    // How far inside the friction cone the contact normals lie, as a share of the
    // cone's half-angle: 1 on the closing line, 0 at the cone's edge.
    const float fm = m[CheckId::friction_cone];
    e["score"] = std::isfinite(fm) && cone_deg > 0.f ? json(fm / cone_deg) : json(nullptr);
    list.push_back(std::move(e));
  }
  return list;
}

Status plan_target(Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                   const robot::GraspCheckConfig& check_cfg, uint32_t top, PlanResult& res, json& report,
                   std::vector<Grasp>* alternates) {
  planner.set_grasp_check(cfg.executability_checks ? &check : nullptr);
  const Status st = planner.plan(res);
  if (st == Status::ok || st == Status::no_grasp)
    report = plan_report(planner, res, st, cfg, check_cfg, check);  // the grasp's joints: before the alternates
  if (st == Status::ok && top > 0) {
    RankedGrasp more[kMaxRankedGrasps];
    const uint32_t n_more = planner.more_grasps(more, top - 1);
    report["grasps"] = ranked_grasps_report(res, more, n_more, cfg, check_cfg);
    if (alternates != nullptr)
      for (uint32_t k = 0; k < n_more; ++k) alternates->push_back(more[k].grasp);
  }
  planner.set_grasp_check(nullptr);
  return st;
}

json objects_report(Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                    const robot::GraspCheckConfig& check_cfg, uint32_t top) {
  json list = json::array();
  const int32_t target = planner.target_object();
  const uint32_t n = planner.object_count();
  for (uint32_t k = 0; k < n; ++k) {
    const ObjectSummary o = planner.object(k);
    json e{{"index", k},
           {"target", static_cast<int32_t>(k) == target},
           {"centroid", vec(o.centroid)},
           {"box", json{{"min", vec(o.box_min)}, {"max", vec(o.box_max)}}},
           {"voxels", o.voxels}};
    planner.set_grasp_check(cfg.executability_checks ? &check : nullptr);
    PlanResult r;
    const Status st = planner.plan_object(k, r);
    if (st == Status::ok) {
      e["status"] = "ok";
      report_grasp(e, r, cfg, check_cfg, check);
      if (top > 0) {
        RankedGrasp more[kMaxRankedGrasps];
        const uint32_t n_more = planner.more_grasps(more, top - 1);
        e["grasps"] = ranked_grasps_report(r, more, n_more, cfg, check_cfg);
      }
    } else if (st == Status::no_grasp) {
      e["status"] = "no_grasp";
      e["reason"] = to_string(r.reason);
      e["message"] = r.message;
    } else {  // an object larger than the build holds
      e["status"] = to_string(st);
      e["error"] = r.message;
    }
    planner.set_grasp_check(nullptr);
    e["timing_us"] = r.stage_us[static_cast<int>(Stage::total)];
    list.push_back(std::move(e));
  }
  return list;
}

void add_objects(json& report, Planner& planner, const PlannerConfig& cfg, robot::Ur5GraspCheck& check,
                 const robot::GraspCheckConfig& check_cfg, uint32_t top) {
  report["objects"] = objects_report(planner, cfg, check, check_cfg, top);
  const uint32_t dropped = planner.objects_dropped();
  report["objects_dropped"] = dropped;
  if (dropped > 0)
    report["note"] = "the scene holds " + std::to_string(planner.object_count() + dropped) +
                     " objects; the build lists " + std::to_string(kMaxObjects) +
                     " (FG_MAX_OBJECTS): those nearest the workspace centre";
}

}  // namespace fg::host
