// Compile-time capacities of the build configuration (config/<preset>/fg_limits.h),
// with defaults for anything left out and the relations between them checked.
#pragma once
#include <cstdint>

#include "fg_limits.h"

#ifndef FG_MAX_VOXELS
#define FG_MAX_VOXELS 98304u
#endif
#ifndef FG_VOXEL_HASH_SLOTS
#define FG_VOXEL_HASH_SLOTS 131072u
#endif
#ifndef FG_MAX_OBJECT_POINTS
#define FG_MAX_OBJECT_POINTS 16384u
#endif
#ifndef FG_HULL_GRID_DIM
#define FG_HULL_GRID_DIM 256u
#endif
#ifndef FG_MAX_CONTOUR_VERTICES
#define FG_MAX_CONTOUR_VERTICES 4096u
#endif
#ifndef FG_MAX_SCAN_LINES
#define FG_MAX_SCAN_LINES 512u
#endif
#ifndef FG_MAX_VIEWPOINTS
#define FG_MAX_VIEWPOINTS 256u
#endif
#ifndef FG_MAX_CANDIDATES
#define FG_MAX_CANDIDATES 512u
#endif
#ifndef FG_RANSAC_MAX_ITERS
#define FG_RANSAC_MAX_ITERS 1024u
#endif
#ifndef FG_MAX_SENSORS
#define FG_MAX_SENSORS 2u
#endif
#ifndef FG_MAX_CHECKED_CANDIDATES
#define FG_MAX_CHECKED_CANDIDATES 64u
#endif
#ifndef FG_MAX_RANKED_GRASPS
#define FG_MAX_RANKED_GRASPS 8u
#endif
#ifndef FG_MAX_OBJECTS
#define FG_MAX_OBJECTS 8u
#endif
#ifndef FG_SIGHT_BINS
#define FG_SIGHT_BINS 256u
#endif
#ifndef FG_REGISTRATION_SAMPLES
#define FG_REGISTRATION_SAMPLES 1024u
#endif
#ifndef FG_VOXEL_CACHE_BITS
#define FG_VOXEL_CACHE_BITS 12u
#endif

namespace fg {
inline constexpr uint32_t kMaxVoxels = FG_MAX_VOXELS;
inline constexpr uint32_t kVoxelHashSlots = FG_VOXEL_HASH_SLOTS;
inline constexpr uint32_t kMaxObjectPoints = FG_MAX_OBJECT_POINTS;
inline constexpr uint32_t kHullGridDim = FG_HULL_GRID_DIM;
inline constexpr uint32_t kMaxContourVertices = FG_MAX_CONTOUR_VERTICES;
inline constexpr uint32_t kMaxScanLines = FG_MAX_SCAN_LINES;
inline constexpr uint32_t kMaxViewpoints = FG_MAX_VIEWPOINTS;
inline constexpr uint32_t kMaxCandidates = FG_MAX_CANDIDATES;
inline constexpr uint32_t kMaxCheckedCandidates = FG_MAX_CHECKED_CANDIDATES;  //!< per plan()
inline constexpr uint32_t kMaxRankedGrasps = FG_MAX_RANKED_GRASPS;            //!< the best and its alternates
inline constexpr uint32_t kMaxObjects = FG_MAX_OBJECTS;  //!< objects a plan lists (the nearest the centre)
inline constexpr uint32_t kRansacMaxIters = FG_RANSAC_MAX_ITERS;
inline constexpr uint32_t kMaxSensors = FG_MAX_SENSORS;
inline constexpr uint32_t kSightBins = FG_SIGHT_BINS;                      //!< per axis, per sensor
inline constexpr uint32_t kVoxelCacheBits = FG_VOXEL_CACHE_BITS;           //!< ingest's cell cache
inline constexpr uint32_t kRegistrationSamples = FG_REGISTRATION_SAMPLES;  //!< head samples the registration pairs

static_assert(kMaxVoxels > 0 && kMaxObjectPoints > 0, "capacities must be positive");
static_assert((kVoxelHashSlots & (kVoxelHashSlots - 1)) == 0, "hash slots must be a power of two");
static_assert(uint64_t{kVoxelHashSlots} * 3 >= uint64_t{kMaxVoxels} * 4,
              "keep the voxel hash at most three quarters full");
static_assert(kMaxObjectPoints <= kMaxVoxels, "the object is a subset of the voxels");
static_assert(kHullGridDim >= 16 && kHullGridDim <= 4096, "hull raster size out of range");
static_assert(kMaxContourVertices >= 8, "contour capacity too small");
static_assert(kMaxRankedGrasps >= 1 && kMaxRankedGrasps <= 256u, "ranked grasps out of range");
static_assert(kMaxObjects >= 1 && kMaxObjects <= 256u, "objects out of range");
static_assert(kMaxCheckedCandidates >= 1 && kMaxCheckedCandidates <= kMaxCandidates,
              "checked candidates: 1 .. FG_MAX_CANDIDATES");
static_assert(kSightBins >= 16 && kSightBins <= 1024, "sight map size out of range");
static_assert(kVoxelCacheBits >= 4 && kVoxelCacheBits <= 16, "voxel cache size out of range");

//! floor(log2(v)) for v >= 1 (0 for v <= 1), at compile time: power-of-two sizing.
constexpr uint32_t floor_log2(uint64_t v) {
  uint32_t n = 0;
  for (; v > 1; v /= 2) ++n;
  return n;
}
}  // namespace fg
