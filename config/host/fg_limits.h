/* Capacities of the host build configuration: sized for two 640x480 depth sensors
 * at the default 5 mm voxel leaf inside the default workspace crop box.
 * Every value here is a compile-time constant; core/include/fg/core/limits.hpp
 * supplies defaults for anything a configuration leaves out and checks the relations. */
#ifndef FG_LIMITS_H
#define FG_LIMITS_H

#define FG_MAX_VOXELS 98304u           /* occupied voxels of the merged cloud */
#define FG_VOXEL_HASH_SLOTS 131072u    /* open-addressing slots, a power of two >= 4/3 x voxels */
#define FG_MAX_OBJECT_POINTS 16384u    /* voxel centroids of the target object */
#define FG_HULL_GRID_DIM 256u          /* silhouette raster is at most DIM x DIM cells */
#define FG_MAX_CONTOUR_VERTICES 4096u  /* concave hull polygon */
#define FG_MAX_SCAN_LINES 512u         /* scan lines over one silhouette */
#define FG_MAX_VIEWPOINTS 256u         /* virtual viewpoints over all families */
#define FG_MAX_CANDIDATES 512u         /* ranked grasp candidates kept for the checks */
#define FG_MAX_CHECKED_CANDIDATES 128u /* candidates the executability checks examine per plan */
#define FG_MAX_RANKED_GRASPS 16u       /* grasps one ranked plan returns (the best and its alternates) */
#define FG_MAX_OBJECTS 16u        /* objects on the support plane a plan lists (the nearest the workspace centre) */
#define FG_RANSAC_MAX_ITERS 1024u /* upper bound of the configured iteration count */
#define FG_MAX_SENSORS 2u         /* head and hand */
#define FG_SIGHT_BINS 256u        /* nearest-return direction bins per axis, per sensor */
#define FG_VOXEL_CACHE_BITS 13u   /* 2^bits recent cells cached by the ingest loop; then the lookup filter (64 KiB) */

/* The workspace budget: firmware_api's FG_WORKSPACE_SIZE, a compile-time upper bound of
 * fg_workspace_size() (checked by a static_assert in firmware_api/src/fg_api.cpp). */
#define FG_WORKSPACE_SIZE 4194304u /* 4 MiB */

#endif
