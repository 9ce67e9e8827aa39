/* Capacities of the Cortex-M7 build configuration (the cortex-m7 preset): one small
 * cloud of a few thousand points, e.g. a downsampled or cropped depth image, planned
 * in the on-chip and board SRAM of a microcontroller. Same macros as config/host;
 * core/include/fg/core/limits.hpp supplies defaults and checks the relations. */
#ifndef FG_LIMITS_H
#define FG_LIMITS_H

#define FG_MAX_VOXELS 4096u           /* occupied voxels of the merged cloud */
#define FG_VOXEL_HASH_SLOTS 8192u     /* open-addressing slots, a power of two >= 4/3 x voxels */
#define FG_MAX_OBJECT_POINTS 1024u    /* voxel centroids of the target object */
#define FG_HULL_GRID_DIM 64u          /* silhouette raster is at most DIM x DIM cells */
#define FG_MAX_CONTOUR_VERTICES 512u  /* concave hull polygon */
#define FG_MAX_SCAN_LINES 128u        /* scan lines over one silhouette */
#define FG_MAX_VIEWPOINTS 96u         /* virtual viewpoints over all families */
#define FG_MAX_CANDIDATES 128u        /* ranked grasp candidates kept for the checks */
#define FG_MAX_CHECKED_CANDIDATES 32u /* candidates the executability checks examine per plan */
#define FG_MAX_RANKED_GRASPS 8u       /* grasps one ranked plan returns (the best and its alternates) */
#define FG_MAX_OBJECTS 8u             /* objects on the support plane a plan lists (the nearest the workspace centre) */
#define FG_RANSAC_MAX_ITERS 256u      /* upper bound of the configured iteration count */
#define FG_MAX_SENSORS 2u             /* head and hand */
#define FG_SIGHT_BINS 64u             /* nearest-return direction bins per axis, per sensor */
#define FG_REGISTRATION_SAMPLES 160u  /* head voxel centroids the hand is registered to (56 B each, per-view memory) */
#define FG_VOXEL_CACHE_BITS 8u        /* 2^bits recent cells cached by the ingest loop */

/* The workspace budget: firmware_api's FG_WORKSPACE_SIZE, a compile-time upper bound of
 * fg_workspace_size() (checked by a static_assert in firmware_api/src/fg_api.cpp).
 * Kept close to the real size (228.2 KiB) because firmware reserves FG_WORKSPACE_SIZE
 * bytes statically; the configuration's limit is 512 KiB. */
#define FG_WORKSPACE_SIZE 234496u /* 229 KiB */

#endif
