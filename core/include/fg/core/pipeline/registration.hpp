// Stage A.4b, registration: the hand sensor's pose comes from the arm's kinematics and a
// hand-eye calibration, both a few millimetres and a degree off on a real robot, so its
// surfaces land beside the head sensor's and the merged object looks thicker and
// rougher than it is. When the hand's cloud arrives after the head's, its first pass
// fills only its maps of depths per direction (in its own frame); this stage then
// aligns that surface to the head's voxels, and the second pass adds the hand's points with
// the corrected pose. The alignment is point-to-plane ICP from a sample of the head's
// voxel centroids (means, so unbiased by noise) to the hand's surface, found by
// projecting each into the hand's map of mean depths, with the normal from that map's
// neighbouring bins (O(1) per pair, no search structure). A Tukey kernel whose gate
// shrinks over the iterations keeps mismatched pairs (edges, occlusions) out; directions
// the pairs do not constrain (a bare table leaves slide and spin in its plane free) are
// not moved. docs/method.md, "A.4b registration".
#pragma once
#include <cstdint>
#include <limits>

#include "fg/core/pipeline/sensor_views.hpp"
#include "fg/core/types.hpp"
#include "fg/core/voxel_grid.hpp"

namespace fg {

//! The hand's depths per direction bin (the sight map's bins, two by two: x/z, y/z in
//! [-1, 1), kMomentBins per axis), gathered by the first pass over its cloud: their sum,
//! sum of squares and count, so a bin's mean is its surface's depth, unbiased by noise
//! (the sight map keeps the nearest return, which noise pulls toward the sensor).
inline constexpr uint32_t kMomentBins = kSightBins / 2;
struct DepthMoments {
  float sum, sq, n;
};

//! Scratch floats per head sample (register_hand's `scratch`).
inline constexpr uint32_t kRegistrationSampleFloats = 14;
//! The sample picking's work memory, after the samples in register_hand's `scratch`: a
//! class per voxel of its first pass (4 bits; at most 4 per sample), the classes met per
//! cell of kSelectCellBins^2 head sight bins (a byte), and two bits per cell (wanted,
//! dense); in 64-bit words. The slide's samples borrow it afterwards.
inline constexpr uint32_t kSelectCellBins = 4;
inline constexpr uint32_t kSelectCells = kSightBins / kSelectCellBins;
inline constexpr size_t kSelectionClassBytes = size_t{2} * kRegistrationSamples + size_t{kSelectCells} * kSelectCells;
inline constexpr size_t kSelectCellWords = (size_t{kSelectCells} * kSelectCells + 63) / 64;
inline constexpr size_t kSelectionWords = (kSelectionClassBytes + 7) / 8 + 2 * kSelectCellWords;
//! register_hand's scratch in floats: kRegistrationSamples samples, then the picking's work.
inline constexpr size_t kRegistrationScratchFloats =
    size_t{kRegistrationSampleFloats} * kRegistrationSamples + 2 * kSelectionWords;

//! What the registration did with the hand sensor's pose.
enum class RegistrationOutcome : uint8_t {
  not_run = 0,         //!< one sensor, registration off, or no plan yet
  corrected,           //!< the hand's points were moved by `correction`
  calibration_kept,    //!< the calibration agreed: the correction found was below the noise
  too_little_overlap,  //!< too few surfaces both sensors saw: fused as calibrated
  implausible,         //!< the best alignment lies beyond the capture range: fused as calibrated
  hand_added_first,    //!< the hand's points joined the grid before the head's: fused as calibrated
  //! As they would be fused, the hand saw through surfaces the head saw (see_through):
  //! one sensor's points are left out (`left_out`) and the plan is the other's alone
  //! (RegistrationMode::strict: plan() refuses with Status::sensor_disagreement).
  sensor_disagreement,
};
const char* to_string(RegistrationOutcome o);

//! How the planner treats the two sensors (Planner::set_registration).
enum class RegistrationMode : uint8_t {
  off = 0,  //!< fuse with the poses as given
  on,       //!< register the hand to the head before fusing (the default)
  strict,   //!< the same, and a sensor_disagreement is an error rather than the head's plan
};

struct RegistrationResult {
  RegistrationOutcome outcome = RegistrationOutcome::not_run;
  //! World-frame rigid map from the hand's points as calibrated to where they belong:
  //! the corrected hand pose is correction * world_T_hand. Identity unless corrected.
  Pose correction;
  float translation_mm = 0.f;      //!< of the hand sensor's origin under `correction`
  float rotation_deg = 0.f;        //!< angle of correction.R
  float residual_before_mm = 0.f;  //!< RMS point-to-plane distance of the pairs, as calibrated
  float residual_mm = 0.f;         //!< the same after the correction (= before unless corrected)
  float overlap = 0.f;             //!< share of the head's samples the hand saw within the final gate
  uint32_t pairs = 0;              //!< those pairs
  uint32_t samples = 0;            //!< head samples tried (in the hand's view or not)
  uint32_t iterations = 0;
  //! Of the head's samples where the hand, at the pose the fusion uses, saw a surface
  //! (`compared`), the share more than see_through_m in front of that surface.
  float see_through = 0.f;
  uint32_t compared = 0;
  //! On sensor_disagreement, each sensor's table as its own surfaces place it (the mean
  //! normal of its samples within 30 deg of world up, then of those within 10 deg of
  //! that; the hand at its given pose): degrees off level. NaN otherwise, or with too
  //! few such samples. The world's table is level (z up).
  float head_tilt_deg = std::numeric_limits<float>::quiet_NaN();
  float hand_tilt_deg = std::numeric_limits<float>::quiet_NaN();
  //! On sensor_disagreement, the sensor whose points are left out: the hand, unless the
  //! head's table is off level by more than level_tilt and the hand's is not.
  SensorRole left_out = SensorRole::hand;
  uint32_t us = 0;  //!< the stage's time (platform clock)

  //! The hand pose the fusion uses: correction * given when corrected, else given.
  Pose hand_pose(const Pose& given) const;
};

//! Bounds and thresholds of the stage, with their physical meaning.
struct RegistrationParams {
  //! Head voxel centroids taken, spread over the cloud: at most kRegistrationSamples,
  //! the scratch's room (more are not taken).
  uint32_t max_samples = 1024;
  uint32_t max_iterations = 24;       //!< each a pass over the samples and a 6x6 solve
  float gate_start_m = 0.04f;         //!< pairs farther apart are not pairs: the capture range
  float gate_end_m = 0.008f;          //!< the final gate: a few times the sensors' noise
  float min_correction_m = 0.0015f;   //!< a smaller move (at the samples' extent) is noise
  float min_cost_drop = 0.05f;        //!< a correction lowers the robust cost by this share at least
  float max_translation_m = 0.05f;    //!< beyond these the alignment is not believed
  float max_rotation_rad = 0.10472f;  //!< 6 deg
  uint32_t min_pairs = 64;            //!< fewer final pairs: not enough overlap (the planner: samples / 16)
  float min_overlap = 0.05f;          //!< nor when under this share of the samples
  float see_through_m = 0.02f;        //!< a head sample this far in front of the hand's surface is seen through
  float max_see_through = 0.2f;       //!< a larger share of the compared samples: sensor_disagreement
  //! A table seen more than this off level says its sensor's pose is off: the contract's
  //! table is level. The head's estimate reads up to 2 deg off on an exact pose (its
  //! normals come from nearest returns, pulled toward the sensor), the hand's less.
  float level_tilt_rad = 0.0524f;   //!< 3 deg
  uint32_t min_level_samples = 32;  //!< fewer samples facing up: no tilt measured (NaN)
  //! The slide in the table's plane, searched after the alignment on the samples off the
  //! table: the coarse grid's step (it reaches 3 steps each way, then three 3 x 3 grids
  //! each half as fine refine it); what it must explain of the samples' misfit (each
  //! sample's capped at gate_end^2), in samples' worth and as a share; and the fewest
  //! samples it needs.
  float slide_step_m = 0.005f;
  float min_slide_gain_samples = 5.f;
  float min_slide_gain = 0.05f;
  uint32_t min_slide_samples = 32;
};

//! The registration of the hand's surface, `moments` (kMomentBins^2 bins) seen from
//! views.pose[hand] (world_T_sensor as given), to the head's points, which `grid`
//! (before finalize()) holds alone, their normals from the head's sight map in `views`.
//! `scratch` holds kRegistrationScratchFloats floats, 8-byte aligned. Changes
//! nothing: the caller ingests the hand's points with the corrected pose.
//! Deterministic; at most max_iterations passes over at most max_samples samples.
RegistrationResult register_hand(const VoxelGrid& grid, const SensorViews& views, const DepthMoments* moments,
                                 const RegistrationParams& params, float* scratch);

}  // namespace fg
