// `forcegrasp sim`: the whole grasp task (firmware_api's GraspTask) on the simulated
// hardware of hal/sim: a seeded scene, the head camera on its mount, the wrist camera
// on a UR5 that follows joint commands, a 2F-85-class gripper closing on the true
// geometry. Each trial is judged on the TRUE geometry. Host only.
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "fg/core/config.hpp"
#include "fg/core/planner.hpp"
#include "sim/scene_gen.hpp"

namespace fg::host {

struct SimOptions {
  std::vector<std::string> kinds;  //!< object kinds (hal/sim scene_gen names)
  uint32_t trials = 0;             //!< 0: 20 per kind
  uint64_t seed = 1;               //!< trial i: kind i % kinds, seed + i
  //! Which scenes (hal/sim scene_gen.hpp); the program's default is cell, and the tests
  //! that pin seeds of the project's own spread ask for classic.
  sim::Distribution distribution = sim::Distribution::cell;
  double mu = 0.5;                  //!< friction coefficient of the judge
  std::string pictures_dir;         //!< per trial: SVG pictures of the plan
  std::string export_dir;           //!< per trial: scene.json + PCD + truth.json
  std::string json_path;            //!< per trial records and the table, as JSON
  bool progress = true;             //!< a progress line on stderr
  double second_object_rate = 0.3;  //!< classic only (cell draws 0-3 other objects)
  //! --calibration-error MM,DEG: the wrist sensor's pose the task believes is off the
  //! true one by this much in each trial (a hand-eye error: a translation of MM in a
  //! random direction and a turn of DEG about a random axis through the sensor, drawn
  //! from the trial's seed); the camera itself stays where the arm holds it.
  double calibration_error_mm = 0.0, calibration_error_deg = 0.0;
  //! The head sensor's pose the task believes, off by MM millimetres and DEG degrees in
  //! each trial, in a direction of its own drawn from the trial's seed (--head-error).
  double head_error_mm = 0.0, head_error_deg = 0.0;
  //! --kinematic-error MM,DEG: the arm's true kinematics off the nominal UR5 the task
  //! computes with (sim::with_kinematic_error: every DH length within MM, every joint's
  //! zero within DEG, drawn from the trial's seed), as an uncalibrated arm's are. The
  //! wrist camera then sits where the true arm holds it, and the gripper goes where the
  //! true arm takes it.
  double kinematic_error_mm = 0.0, kinematic_error_deg = 0.0;
  RegistrationMode registration = RegistrationMode::on;  //!< --registration on|off|strict
  //! --sensors both|head|hand: the sensors the task captures and plans from (the arm
  //! still stands at the wrist's viewpoint when the wrist is not used).
  bool use_head = true, use_hand = true;
};

//! "both", "head" or "hand": the sensors of SimOptions (--sensors).
const char* sensors_name(const SimOptions& opt);

//! One trial's outcome.
struct SimTrial {
  std::string kind;
  uint64_t seed = 0;
  bool fits = false;            //!< the target fits the gripper in some direction (truth)
  bool success = false;         //!< lifted with a grasp the judge passes on the true geometry, or
                                //!< no_grasp on a target that fits in no direction
  std::string verdict;          //!< "success", the judge's reason, or the task's failure
  std::string task_state;       //!< the task's final state and failure
  std::string plan_reason;      //!< the planner's no_grasp reason, when it gave one
  bool wrist_view = false;      //!< the arm put the wrist camera at the scene's viewpoint
                                //!< (else it looked from its home pose)
  double plan_ms = 0.0;         //!< the planner's own time (the plan() call)
  double width_error_m = -1.0;  //!< |reported - true width| of a judged grasp, else -1
  double task_s = 0.0;          //!< simulated time from start to the end of the task
  uint32_t ticks = 0;
  // The planned grasp (when the plan gave one) and what the judge measured on it.
  bool has_grasp = false;
  Grasp grasp;
  float angle_left = -1.f, angle_right = -1.f;  //!< friction angles at the contacts (rad), -1 unknown
  float true_width = -1.f;                      //!< pad-to-pad width on the true geometry (m), -1 unknown
  Vec3 contact_left = Vec3::Zero(), contact_right = Vec3::Zero();  //!< first contacts (world), when true_width >= 0
  // The hand sensor's registration (A.4b), and how far its pose was off at the target
  // (mm: where a point of the target seen by the hand lands, against the truth) as
  // given and as the planner used it; -1 when the wrist did not look from the
  // scene's viewpoint.
  std::string registration;
  double hand_error_given_mm = -1.0, hand_error_used_mm = -1.0;
  uint32_t relooks = 0;  //!< times the task's wrist sensor looked again from an advised view
  // After a refusal as occluded that said which sensor would have to look where: one
  // more plan with that sensor looking from there (plan_after_advised_look), "success"
  // or why not; empty otherwise.
  std::string relook;
};

//! Runs one trial with the planner configuration `cfg`. `planner` is reused between
//! trials (it is large). Pictures and export go to subfolders <kind>-<seed>.
[[nodiscard]] SimTrial run_sim_trial(const std::string& kind, uint64_t seed, const SimOptions& opt,
                                     const PlannerConfig& cfg, Planner& planner);

//! Runs every trial, prints the table on stdout; returns the per-trial records and the
//! table as JSON.
nlohmann::json run_sim(const SimOptions& opt, const PlannerConfig& cfg, Planner& planner);

}  // namespace fg::host
