/* Drives the whole firmware C API from C99, as controller firmware would: sizes and
 * versions, every status string, config checks, fg_init's refusals, calls in the
 * wrong order or with bad pointers, a two-sensor plan on a ray-cast scene (a box
 * narrower than the opening in x only, on a table) with its object list, the object's
 * own plan and targets, two workspaces side by side, and bit-identical repeats. Exit
 * status 0 when every check passes. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "forcegrasp/forcegrasp.h"

static int g_failures = 0;
#define CHECK(cond)                                                            \
  do {                                                                         \
    if (!(cond)) {                                                             \
      ++g_failures;                                                            \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                          \
  } while (0)
#define CHECK_STATUS(call, expected)                                                                          \
  do {                                                                                                        \
    const fg_status got_ = (call);                                                                            \
    if (got_ != (expected)) {                                                                                 \
      ++g_failures;                                                                                           \
      fprintf(stderr, "%s:%d: %s returned %s, expected %s\n", __FILE__, __LINE__, #call, fg_status_str(got_), \
              fg_status_str(expected));                                                                       \
    }                                                                                                         \
  } while (0)

static FG_WORKSPACE_STORAGE(g_mem_a);
static FG_WORKSPACE_STORAGE(g_mem_b);
static FG_WORKSPACE_STORAGE(g_mem_copy);

/* ---- a tiny ray caster: the table z = 0 and one axis-aligned box ---- */
typedef struct {
  float lo[3], hi[3];
} box3;

typedef struct {
  fg_pose pose; /* world_T_sensor */
  fg_intrinsics k;
  uint16_t width, height;
} camera;

/* Depth (sensor z, m) of the first hit along pixel (u, v); 0 when nothing is hit. */
static float cast(const camera *c, const box3 *b, int u, int v) {
  const float d[3] = {((float)u - c->k.cx) / c->k.fx, ((float)v - c->k.cy) / c->k.fy, 1.f};
  float o[3], w[3];
  float best = 1e9f, t0 = 0.f, t1 = 1e9f;
  size_t i;
  int hit_box = 1;
  for (i = 0; i < 3; ++i) {
    o[i] = c->pose.t[i];
    w[i] = c->pose.r[3 * i] * d[0] + c->pose.r[3 * i + 1] * d[1] + c->pose.r[3 * i + 2] * d[2];
  }
  if (w[2] < -1e-6f) best = -o[2] / w[2]; /* table */
  for (i = 0; i < 3 && hit_box; ++i) {    /* slab test */
    if (fabsf(w[i]) < 1e-9f) {
      if (o[i] < b->lo[i] || o[i] > b->hi[i]) hit_box = 0;
    } else {
      float a = (b->lo[i] - o[i]) / w[i], z = (b->hi[i] - o[i]) / w[i];
      if (a > z) {
        const float s = a;
        a = z;
        z = s;
      }
      if (a > t0) t0 = a;
      if (z < t1) t1 = z;
      if (t0 > t1) hit_box = 0;
    }
  }
  if (hit_box && t0 > 0.f && t0 < best) best = t0;
  return best < 1e8f ? best : 0.f; /* d has z = 1: the ray parameter is the depth */
}

static uint16_t g_depth[120 * 160];
static float g_xyz[120 * 160 * 4]; /* x y z pad: a 16-byte stride */

static void look_at(camera *c, const float eye[3], const float target[3]) {
  float f[3], x[3], y[3], n;
  int i;
  for (i = 0; i < 3; ++i) f[i] = target[i] - eye[i];
  n = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (i = 0; i < 3; ++i) f[i] /= n;
  /* x = f x up (world z), y = f x x: an optical frame, x right, y down */
  x[0] = f[1];
  x[1] = -f[0];
  x[2] = 0.f;
  n = sqrtf(x[0] * x[0] + x[1] * x[1]);
  if (n < 1e-6f) { /* looking straight down */
    x[0] = 1.f;
    x[1] = 0.f;
    n = 1.f;
  }
  x[0] /= n;
  x[1] /= n;
  y[0] = f[1] * x[2] - f[2] * x[1];
  y[1] = f[2] * x[0] - f[0] * x[2];
  y[2] = f[0] * x[1] - f[1] * x[0];
  for (i = 0; i < 3; ++i) {
    c->pose.r[3 * i + 0] = x[i];
    c->pose.r[3 * i + 1] = y[i];
    c->pose.r[3 * i + 2] = f[i];
    c->pose.t[i] = eye[i];
  }
  c->width = 160;
  c->height = 120;
  c->k.fx = c->k.fy = 131.25f;
  c->k.cx = 79.5f;
  c->k.cy = 59.5f;
}

static void render_depth(const camera *c, const box3 *b) {
  int u, v;
  for (v = 0; v < c->height; ++v)
    for (u = 0; u < c->width; ++u) {
      const float z = cast(c, b, u, v);
      g_depth[v * c->width + u] = (uint16_t)(z > 0.f ? z * 1000.f + 0.5f : 0.f);
    }
}

/* Sensor-frame points of every pixel; misses become NaN points (which are skipped). */
static size_t render_points(const camera *c, const box3 *b) {
  int u, v;
  size_t n = 0;
  for (v = 0; v < c->height; ++v)
    for (u = 0; u < c->width; ++u, ++n) {
      const float z = cast(c, b, u, v);
      float *p = &g_xyz[4 * n];
      p[0] = z > 0.f ? ((float)u - c->k.cx) / c->k.fx * z : NAN;
      p[1] = ((float)v - c->k.cy) / c->k.fy * z;
      p[2] = z;
      p[3] = 0.f;
    }
  return n;
}

static void small_config(fg_config *cfg) {
  CHECK_STATUS(fg_config_default(cfg), FG_OK);
  cfg->crop_half_x_m = 0.25f; /* a small table patch keeps the voxel count low */
  cfg->crop_half_y_m = 0.25f;
}

/* Both sensors see `b`: the head from above through a depth image, the hand from the
 * side through a point array. */
static fg_status capture_and_plan(fg_workspace *ws, const box3 *b, fg_grasp *g) {
  camera head, hand;
  const float head_eye[3] = {0.5f, 0.f, 0.9f}, hand_eye[3] = {0.5f, -0.45f, 0.45f};
  const float target[3] = {0.5f, 0.f, 0.05f};
  size_t n;
  fg_status s;
  look_at(&head, head_eye, target);
  look_at(&hand, hand_eye, target);
  render_depth(&head, b);
  s = fg_add_depth_image(ws, FG_SENSOR_HEAD, g_depth, head.width, head.height, &head.k, &head.pose);
  if (s != FG_OK) return s;
  n = render_points(&hand, b);
  s = fg_add_points(ws, FG_SENSOR_HAND, g_xyz, n, 4 * sizeof(float), &hand.pose);
  if (s != FG_OK) return s;
  return fg_plan(ws, g);
}

/* n floats bit for bit (NaN and -0 included), as their bit patterns. */
static int same_floats(const float *a, const float *b, size_t n) {
  size_t i;
  for (i = 0; i < n; ++i) {
    uint32_t x, y;
    memcpy(&x, &a[i], sizeof x);
    memcpy(&y, &b[i], sizeof y);
    if (x != y) return 0;
  }
  return 1;
}

/* Grasps compared without their timings, which differ run to run. */
static int same_grasp(const fg_grasp *a, const fg_grasp *b) {
  return a->reason == b->reason && same_floats(a->position, b->position, 3) &&
         same_floats(a->approach, b->approach, 3) && same_floats(a->closing, b->closing, 3) &&
         same_floats(a->pregrasp, b->pregrasp, 3) && same_floats(&a->width_m, &b->width_m, 1) &&
         same_floats(&a->beta_rad, &b->beta_rad, 1) && same_floats(&a->dz_m, &b->dz_m, 1) &&
         a->points_input == b->points_input && a->points_finite == b->points_finite &&
         a->points_kept == b->points_kept && a->voxels == b->voxels && a->plane_voxels == b->plane_voxels &&
         a->object_voxels == b->object_voxels && a->viewpoints == b->viewpoints && a->candidates == b->candidates;
}

static void test_versions_and_sizes(void) {
  CHECK(fg_version() == ((FG_VERSION_MAJOR << 16) | (FG_VERSION_MINOR << 8) | FG_VERSION_PATCH));
  CHECK(fg_abi_version() == FG_ABI_VERSION);
  CHECK(fg_workspace_size() > 0 && fg_workspace_size() <= FG_WORKSPACE_SIZE);
  CHECK(fg_workspace_align() == FG_WORKSPACE_ALIGN);
  CHECK(((uintptr_t)g_mem_a) % FG_WORKSPACE_ALIGN == 0);
  printf("workspace: %lu bytes (budget FG_WORKSPACE_SIZE %lu), align %lu, version 0x%06lx\n",
         (unsigned long)fg_workspace_size(), (unsigned long)FG_WORKSPACE_SIZE, (unsigned long)fg_workspace_align(),
         (unsigned long)fg_version());
}

static void test_status_strings(void) {
  static const fg_status all[] = {FG_OK,
                                  FG_NO_GRASP,
                                  FG_ERR_INVALID_ARGUMENT,
                                  FG_ERR_NON_FINITE,
                                  FG_ERR_INVALID_POSE,
                                  FG_ERR_INVALID_CONFIG,
                                  FG_ERR_NO_INPUT,
                                  FG_ERR_INVALID_SENSOR,
                                  FG_ERR_INVALID_SEQUENCE,
                                  FG_ERR_WORKSPACE_TOO_SMALL,
                                  FG_ERR_WORKSPACE_MISALIGNED,
                                  FG_ERR_ABI_MISMATCH,
                                  FG_ERR_CONFIG_SIZE,
                                  FG_ERR_NOT_A_WORKSPACE,
                                  FG_ERR_CAPACITY_EXCEEDED,
                                  FG_ERR_NUMERIC_FAILURE,
                                  FG_ERR_INTERNAL};
  size_t i, j;
  for (i = 0; i < sizeof all / sizeof all[0]; ++i) {
    const char *s = fg_status_str(all[i]);
    CHECK(s != NULL && strncmp(s, "FG_", 3) == 0 && strcmp(s, "FG_UNKNOWN_STATUS") != 0);
    for (j = 0; j < i; ++j) CHECK(strcmp(s, fg_status_str(all[j])) != 0);
  }
  CHECK(strcmp(fg_status_str(12345), "FG_UNKNOWN_STATUS") == 0);
  CHECK(strcmp(fg_status_str(FG_ERR_INVALID_POSE), "FG_ERR_INVALID_POSE") == 0);
  CHECK(strcmp(fg_reason_str(FG_REASON_TOO_WIDE), "too_wide") == 0);
  CHECK(strcmp(fg_reason_str(FG_REASON_OCCLUDED), "occluded") == 0);
  CHECK(strcmp(fg_reason_str(-5), "unknown_reason") == 0 && strcmp(fg_reason_str(12), "unknown_reason") == 0);
  {
    /* Every reason has a name of its own. */
    int r, q;
    for (r = FG_REASON_NONE; r <= FG_REASON_OCCLUDED; ++r) {
      CHECK(strcmp(fg_reason_str(r), "unknown_reason") != 0);
      for (q = FG_REASON_NONE; q < r; ++q) CHECK(strcmp(fg_reason_str(r), fg_reason_str(q)) != 0);
    }
  }
}

static void test_config(void) {
  fg_config cfg;
  const char *field = NULL;
  CHECK_STATUS(fg_config_default(NULL), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  CHECK(cfg.struct_size == sizeof(fg_config) && cfg.abi_version == FG_ABI_VERSION);
  CHECK(fabsf(cfg.voxel_leaf_m - 0.005f) < 1e-9f && fabsf(cfg.gripper.max_opening_m - 0.085f) < 1e-9f);
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_OK);
  CHECK(field != NULL && field[0] == '\0');
  CHECK_STATUS(fg_config_check(NULL, &field), FG_ERR_INVALID_ARGUMENT);

  cfg.voxel_leaf_m = -1.f;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK(field != NULL && strcmp(field, "voxel_leaf") == 0);
  cfg.voxel_leaf_m = NAN;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.paper_depth = 2;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK(strcmp(field, "paper_depth") == 0);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.target_rule = 9;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK(strcmp(field, "target_rule") == 0);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.gripper.max_opening_m = 0.f;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK(strcmp(field, "gripper.max_opening") == 0);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.struct_size = sizeof(fg_config) - 4; /* a caller built against another header */
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_CONFIG_SIZE);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.abi_version = FG_ABI_VERSION + 1;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_ABI_MISMATCH);
  CHECK_STATUS(fg_config_default(&cfg), FG_OK);
  cfg.ransac_iterations = 0xFFFFFFFFu;
  CHECK_STATUS(fg_config_check(&cfg, &field), FG_ERR_INVALID_CONFIG);
  CHECK(strcmp(field, "ransac_iterations") == 0);
}

static void test_init_refusals(void) {
  fg_config cfg;
  fg_workspace *ws = (fg_workspace *)&g_mem_b; /* must be overwritten with NULL */
  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, NULL), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_init(NULL, sizeof g_mem_a, &cfg, &ws), FG_ERR_INVALID_ARGUMENT);
  CHECK(ws == NULL);
  CHECK_STATUS(fg_init(g_mem_a + 1, sizeof g_mem_a - 1, &cfg, &ws), FG_ERR_WORKSPACE_MISALIGNED);
  CHECK_STATUS(fg_init(g_mem_a + 8, sizeof g_mem_a - 8, &cfg, &ws), FG_ERR_WORKSPACE_MISALIGNED);
  CHECK_STATUS(fg_init(g_mem_a, fg_workspace_size() - 1, &cfg, &ws), FG_ERR_WORKSPACE_TOO_SMALL);
  CHECK_STATUS(fg_init(g_mem_a, 0, &cfg, &ws), FG_ERR_WORKSPACE_TOO_SMALL);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, NULL, &ws), FG_ERR_INVALID_ARGUMENT);
  cfg.dtheta_rad = 0.f;
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &ws), FG_ERR_INVALID_CONFIG);
  CHECK(ws == NULL);
  small_config(&cfg);
  cfg.abi_version = 0;
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &ws), FG_ERR_ABI_MISMATCH);
  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, fg_workspace_size(), &cfg, &ws), FG_OK); /* exactly enough */
  CHECK(ws != NULL && (void *)ws == (void *)g_mem_a);
}

static void test_wrong_order_and_bad_arguments(void) {
  fg_config cfg;
  fg_workspace *ws = NULL;
  fg_grasp g;
  const float pts[6] = {0.5f, 0.f, 0.8f, 0.51f, 0.f, 0.8f};
  const uint16_t depth[4] = {800, 800, 800, 800};
  fg_intrinsics k = {100.f, 100.f, 0.5f, 0.5f};
  fg_pose pose = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
  unsigned char junk[64];

  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &ws), FG_OK);
  /* Not a workspace. */
  memset(junk, 0, sizeof junk);
  CHECK_STATUS(fg_plan(NULL, &g), FG_ERR_NOT_A_WORKSPACE);
  CHECK_STATUS(fg_plan((fg_workspace *)junk, &g), FG_ERR_NOT_A_WORKSPACE);
  {
    uint32_t n_ranked = 7;
    CHECK_STATUS(fg_plan_ranked(NULL, &g, 1, &n_ranked), FG_ERR_NOT_A_WORKSPACE);
  }
  CHECK_STATUS(fg_reset(NULL), FG_ERR_NOT_A_WORKSPACE);
  CHECK_STATUS(fg_add_points(NULL, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_ERR_NOT_A_WORKSPACE);
  CHECK_STATUS(fg_add_depth_image((fg_workspace *)junk, FG_SENSOR_HEAD, depth, 2, 2, &k, &pose),
               FG_ERR_NOT_A_WORKSPACE);
  CHECK(fg_last_message(NULL) != NULL && fg_last_message(NULL)[0] != '\0');
  /* A byte copy is not a workspace either: it would share nothing with the original. */
  memcpy(g_mem_copy, g_mem_a, fg_workspace_size());
  CHECK_STATUS(fg_plan((fg_workspace *)g_mem_copy, &g), FG_ERR_NOT_A_WORKSPACE);
  {
    /* The target and object calls too. */
    const float at[3] = {0.5f, 0.f, 0.05f}, lo[3] = {0.4f, -0.1f, 0.f}, hi[3] = {0.6f, 0.1f, 0.2f};
    fg_object objects[2];
    uint32_t n_objects = 7, n_dropped = 7;
    CHECK_STATUS(fg_set_target_point(NULL, at), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_set_target_box((fg_workspace *)junk, lo, hi), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_clear_target(NULL), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_set_sensor_units(NULL, FG_SENSOR_HEAD, 0.001f), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_objects(NULL, objects, 2, &n_objects, &n_dropped), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_plan_object((fg_workspace *)junk, 0, &g), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_plan_object_ranked(NULL, 0, &g, 1, &n_objects), FG_ERR_NOT_A_WORKSPACE);
    CHECK_STATUS(fg_objects((fg_workspace *)g_mem_copy, objects, 2, &n_objects, NULL), FG_ERR_NOT_A_WORKSPACE);
  }

  /* Plan before data. */
  CHECK_STATUS(fg_plan(ws, &g), FG_ERR_NO_INPUT);
  CHECK(fg_last_message(ws)[0] != '\0');
  CHECK_STATUS(fg_plan(ws, NULL), FG_ERR_INVALID_ARGUMENT);
  /* Bad pointers, roles, strides, poses. */
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, NULL, 2, 12, &pose), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, NULL), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 4, &pose), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_add_points(ws, 7, pts, 2, 12, &pose), FG_ERR_INVALID_SENSOR);
  CHECK_STATUS(fg_add_points(ws, -1, pts, 2, 12, &pose), FG_ERR_INVALID_SENSOR);
  CHECK_STATUS(fg_add_points(ws, 256, pts, 2, 12, &pose), FG_ERR_INVALID_SENSOR);
  CHECK_STATUS(fg_add_depth_image(ws, FG_SENSOR_HEAD, NULL, 2, 2, &k, &pose), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_add_depth_image(ws, FG_SENSOR_HEAD, depth, 2, 2, NULL, &pose), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_add_depth_image(ws, FG_SENSOR_HEAD, depth, 0, 2, &k, &pose), FG_ERR_INVALID_ARGUMENT);
  k.fx = NAN;
  CHECK_STATUS(fg_add_depth_image(ws, FG_SENSOR_HEAD, depth, 2, 2, &k, &pose), FG_ERR_NON_FINITE);
  k.fx = 100.f;
  pose.t[0] = INFINITY;
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_ERR_NON_FINITE);
  pose.t[0] = 0.f;
  pose.r[0] = 2.f; /* not orthonormal */
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_ERR_INVALID_POSE);
  CHECK(strstr(fg_last_message(ws), "orthonormal") != NULL);
  pose.r[0] = 1.f;
  pose.r[8] = -1.f; /* a reflection */
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_ERR_INVALID_POSE);
  pose.r[8] = 1.f;
  /* The same role twice, then data after plan. */
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_OK);
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 2, 12, &pose), FG_ERR_INVALID_SENSOR);
  CHECK(fg_plan(ws, &g) > FG_ERR_INVALID_ARGUMENT); /* two points: a defined no-grasp */
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HAND, pts, 2, 12, &pose), FG_ERR_INVALID_SEQUENCE);
  CHECK_STATUS(fg_reset(ws), FG_OK);
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HAND, pts, 2, 12, &pose), FG_OK);
  /* The target and object calls: null pointers, bad numbers, object calls before fg_plan. */
  {
    const float at[3] = {0.5f, 0.f, 0.05f}, lo[3] = {0.4f, -0.1f, 0.f}, hi[3] = {0.6f, 0.1f, 0.2f};
    const float nan_at[3] = {0.5f, NAN, 0.05f};
    fg_object objects[2];
    fg_grasp ranked[2];
    uint32_t n_objects = 7, n_dropped = 7;
    CHECK_STATUS(fg_reset(ws), FG_OK);
    CHECK_STATUS(fg_set_target_point(ws, NULL), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_set_target_point(ws, nan_at), FG_ERR_NON_FINITE);
    CHECK_STATUS(fg_set_target_box(ws, NULL, hi), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_set_target_box(ws, lo, NULL), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_set_target_box(ws, hi, lo), FG_ERR_INVALID_ARGUMENT); /* minimum above maximum */
    CHECK(strstr(fg_last_message(ws), "target box") != NULL);
    CHECK_STATUS(fg_set_target_point(ws, at), FG_OK);
    CHECK_STATUS(fg_clear_target(ws), FG_OK);
    CHECK_STATUS(fg_set_sensor_units(ws, 9, 1.f), FG_ERR_INVALID_SENSOR);
    CHECK_STATUS(fg_set_sensor_units(ws, FG_SENSOR_HAND, 0.f), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_set_sensor_units(ws, FG_SENSOR_HAND, NAN), FG_ERR_NON_FINITE);
    CHECK(strstr(fg_last_message(ws), "units") != NULL);
    CHECK_STATUS(fg_set_sensor_units(ws, FG_SENSOR_HAND, 0.001f), FG_OK);
    CHECK_STATUS(fg_set_sensor_units(ws, FG_SENSOR_HAND, 1.f), FG_OK);
    CHECK_STATUS(fg_objects(ws, NULL, 2, &n_objects, &n_dropped), FG_ERR_INVALID_ARGUMENT);
    CHECK(n_objects == 0 && n_dropped == 0);
    CHECK_STATUS(fg_objects(ws, objects, 2, NULL, &n_dropped), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_objects(ws, objects, 0, &n_objects, &n_dropped), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_objects(ws, objects, 2, &n_objects, NULL), FG_OK); /* before fg_plan: none */
    CHECK(n_objects == 0);
    CHECK_STATUS(fg_plan_object(ws, 0, NULL), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_plan_object(ws, 0, &g), FG_ERR_INVALID_SEQUENCE);
    CHECK_STATUS(fg_plan_object_ranked(ws, 0, ranked, 2, &n_objects), FG_ERR_INVALID_SEQUENCE);
    CHECK_STATUS(fg_plan_object_ranked(ws, 0, NULL, 2, &n_objects), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_plan_object_ranked(ws, 0, ranked, 0, &n_objects), FG_ERR_INVALID_ARGUMENT);
    CHECK_STATUS(fg_plan_object_ranked(ws, 0, ranked, 2, NULL), FG_ERR_INVALID_ARGUMENT);
  }
  /* Zero points is valid (nothing seen) and plans to no_grasp, reason no_points. */
  CHECK_STATUS(fg_reset(ws), FG_OK);
  CHECK_STATUS(fg_add_points(ws, FG_SENSOR_HEAD, pts, 0, 12, &pose), FG_OK);
  CHECK_STATUS(fg_plan(ws, &g), FG_NO_GRASP);
  CHECK(g.reason == FG_REASON_NO_POINTS);
}

static void test_plan_two_sensors(void) {
  fg_config cfg;
  fg_workspace *ws = NULL;
  fg_grasp g, again;
  const box3 narrow_x = {{0.475f, -0.06f, 0.f}, {0.525f, 0.06f, 0.10f}}; /* 5 x 12 x 10 cm */
  const box3 too_wide = {{0.40f, -0.10f, 0.f}, {0.60f, 0.10f, 0.10f}};   /* 20 x 20 cm */
  fg_status s;
  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &ws), FG_OK);
  s = capture_and_plan(ws, &narrow_x, &g);
  CHECK_STATUS(s, FG_OK);
  printf(
      "box 5x12x10 cm: %s, width %.4f m at (%.3f %.3f %.3f), closing (%.2f %.2f %.2f), "
      "approach (%.2f %.2f %.2f), %u voxels, %u us\n",
      fg_status_str(s), g.width_m, g.position[0], g.position[1], g.position[2], g.closing[0], g.closing[1],
      g.closing[2], g.approach[0], g.approach[1], g.approach[2], g.voxels, g.stage_us[FG_STAGE_TOTAL]);
  CHECK(fabsf(g.closing[0]) > 0.9f); /* across the 5 cm side */
  CHECK(g.width_m > 0.04f && g.width_m < 0.06f);
  CHECK(fabsf(g.position[0] - 0.5f) < 0.02f && fabsf(g.position[1]) < 0.05f);
  CHECK(g.position[2] > 0.f && g.position[2] < 0.11f);
  CHECK(g.points_input == 2u * 160u * 120u && g.object_voxels > 0 && g.voxels >= g.object_voxels);
  /* Planning again without new data gives the same grasp, bit for bit. */
  CHECK_STATUS(fg_plan(ws, &again), FG_OK);
  CHECK(same_grasp(&g, &again));
  /* The objects on the table: the box (its sides seen edge-on by the hand sensor may
   * stand apart as pieces of their own), the target among them, planned for itself
   * alike. */
  {
    fg_object objects[FG_MAX_OBJECTS];
    uint32_t n_objects = 0, n_dropped = 9, k, targets = 0, target = 0;
    const float on_box[3] = {0.5f, 0.f, 0.05f}, outside[3] = {0.5f, 0.f, 3.f};
    CHECK_STATUS(fg_objects(ws, objects, FG_MAX_OBJECTS, &n_objects, &n_dropped), FG_OK);
    CHECK(n_objects >= 1 && n_dropped == 0);
    for (k = 0; k < n_objects; ++k) {
      CHECK(fabsf(objects[k].centroid[0] - 0.5f) < 0.03f && fabsf(objects[k].centroid[1]) < 0.065f);
      CHECK(objects[k].box_min[0] <= objects[k].centroid[0] && objects[k].centroid[0] <= objects[k].box_max[0]);
      if (objects[k].is_target) {
        target = k;
        ++targets;
      }
    }
    CHECK(targets == 1 && objects[target].voxels == g.object_voxels);
    CHECK_STATUS(fg_plan_object(ws, target, &again), FG_OK);
    CHECK(same_floats(again.position, g.position, 3) && again.width_m == g.width_m);
    CHECK_STATUS(fg_plan_object(ws, n_objects, &again), FG_ERR_INVALID_ARGUMENT);
    /* A target on the box gives fg_plan's grasp; one above the crop box is refused. */
    CHECK_STATUS(fg_set_target_point(ws, on_box), FG_OK);
    CHECK_STATUS(fg_plan(ws, &again), FG_OK);
    CHECK(same_floats(again.position, g.position, 3));
    CHECK_STATUS(fg_set_target_point(ws, outside), FG_OK);
    CHECK_STATUS(fg_plan(ws, &again), FG_ERR_INVALID_ARGUMENT);
    CHECK(strstr(fg_last_message(ws), "outside") != NULL);
    CHECK_STATUS(fg_clear_target(ws), FG_OK);
  }
  CHECK_STATUS(fg_plan(ws, &again), FG_OK);
  CHECK(same_grasp(&g, &again));
  /* A new capture of the same scene too. */
  CHECK_STATUS(fg_reset(ws), FG_OK);
  CHECK_STATUS(capture_and_plan(ws, &narrow_x, &again), FG_OK);
  CHECK(same_grasp(&g, &again));
  /* Wider than the opening every way: no grasp, and why. */
  CHECK_STATUS(fg_reset(ws), FG_OK);
  CHECK_STATUS(capture_and_plan(ws, &too_wide, &again), FG_NO_GRASP);
  CHECK(again.reason == FG_REASON_TOO_WIDE || again.reason == FG_REASON_NO_CANDIDATE);
  printf("box 20x20x10 cm: FG_NO_GRASP, reason %s: %s\n", fg_reason_str(again.reason), fg_last_message(ws));
}

/* Two workspaces interleaved give what each gives alone: nothing is shared. */
static void test_two_workspaces(void) {
  fg_config cfg;
  fg_workspace *a = NULL, *b = NULL;
  fg_grasp ga, gb, alone_a, alone_b;
  const box3 box_a = {{0.475f, -0.06f, 0.f}, {0.525f, 0.06f, 0.10f}};
  const box3 box_b = {{0.44f, -0.03f, 0.f}, {0.56f, 0.03f, 0.08f}}; /* narrow in y */
  camera head;
  const float eye[3] = {0.5f, 0.f, 0.9f}, target[3] = {0.5f, 0.f, 0.05f};
  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &a), FG_OK);
  CHECK_STATUS(capture_and_plan(a, &box_a, &alone_a), FG_OK);
  CHECK_STATUS(fg_reset(a), FG_OK);
  CHECK_STATUS(capture_and_plan(a, &box_b, &alone_b), FG_OK);
  CHECK(fabsf(alone_b.closing[1]) > 0.9f);

  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &a), FG_OK);
  CHECK_STATUS(fg_init(g_mem_b, sizeof g_mem_b, &cfg, &b), FG_OK);
  look_at(&head, eye, target);
  render_depth(&head, &box_a);
  CHECK_STATUS(fg_add_depth_image(a, FG_SENSOR_HEAD, g_depth, head.width, head.height, &head.k, &head.pose), FG_OK);
  render_depth(&head, &box_b);
  CHECK_STATUS(fg_add_depth_image(b, FG_SENSOR_HEAD, g_depth, head.width, head.height, &head.k, &head.pose), FG_OK);
  {
    camera hand;
    const float hand_eye[3] = {0.5f, -0.45f, 0.45f};
    size_t n;
    look_at(&hand, hand_eye, target);
    n = render_points(&hand, &box_b);
    CHECK_STATUS(fg_add_points(b, FG_SENSOR_HAND, g_xyz, n, 16, &hand.pose), FG_OK);
    CHECK_STATUS(fg_plan(b, &gb), FG_OK);
    n = render_points(&hand, &box_a);
    CHECK_STATUS(fg_add_points(a, FG_SENSOR_HAND, g_xyz, n, 16, &hand.pose), FG_OK);
    CHECK_STATUS(fg_plan(a, &ga), FG_OK);
  }
  CHECK(same_grasp(&ga, &alone_a));
  CHECK(same_grasp(&gb, &alone_b));
}

/* ---- the grasp task through callbacks: a head sensor replaying the ray caster, an
 * arm that reaches each target in four ticks, a gripper that closes on a set width ---- */
typedef struct {
  uint64_t t_us;
  camera head;
  box3 box;
  int polls, requests;
  double q[6], target[6];
  int arm_left, arm_moves, stops;
  float width, contact_width;
  int grip_left, contact;
} fake_hw;

static uint64_t hw_now(void *c) { return ((fake_hw *)c)->t_us; }
static int32_t hw_request(void *c, int32_t role) {
  fake_hw *h = (fake_hw *)c;
  if (role != FG_SENSOR_HEAD) return 1;
  render_depth(&h->head, &h->box);
  h->polls = 0;
  ++h->requests;
  return 0;
}
static int32_t hw_poll(void *c, int32_t role, fg_depth_frame *out) {
  fake_hw *h = (fake_hw *)c;
  if (role != FG_SENSOR_HEAD || h->requests == 0) return FG_CAPTURE_FAILED;
  if (++h->polls < 3) return FG_CAPTURE_BUSY;
  out->depth_mm = g_depth;
  out->width = h->head.width;
  out->height = h->head.height;
  out->k = h->head.k;
  return FG_CAPTURE_READY;
}
static int32_t hw_move(void *c, const double q[6], double speed) {
  fake_hw *h = (fake_hw *)c;
  int i;
  if (!(speed > 0.0 && speed <= 1.0)) return 1;
  for (i = 0; i < 6; ++i) h->target[i] = q[i];
  h->arm_left = 4;
  ++h->arm_moves;
  return 0;
}
static int32_t hw_arm_read(void *c, fg_arm_state *out) {
  fake_hw *h = (fake_hw *)c;
  int i;
  if (h->arm_left > 0 && --h->arm_left == 0)
    for (i = 0; i < 6; ++i) h->q[i] = h->target[i];
  for (i = 0; i < 6; ++i) out->q[i] = h->q[i];
  out->moving = h->arm_left > 0;
  out->fault = 0;
  return 0;
}
static void hw_stop(void *c) {
  ((fake_hw *)c)->arm_left = 0;
  ++((fake_hw *)c)->stops;
}
static int32_t hw_open(void *c, float w) {
  fake_hw *h = (fake_hw *)c;
  h->width = w;
  h->contact = 0;
  h->grip_left = 2;
  return 0;
}
static int32_t hw_close(void *c, float force) {
  fake_hw *h = (fake_hw *)c;
  (void)force;
  h->contact = h->contact_width > 0.f;
  h->width = h->contact ? h->contact_width : 0.f;
  h->grip_left = 2;
  return 0;
}
static int32_t hw_grip_read(void *c, fg_gripper_state *out) {
  fake_hw *h = (fake_hw *)c;
  if (h->grip_left > 0) --h->grip_left;
  out->width_m = h->width;
  out->moving = h->grip_left > 0;
  out->contact = h->contact && h->grip_left == 0;
  out->fault = 0;
  return 0;
}

static fg_hal_ops make_ops(fake_hw *hw) {
  fg_hal_ops ops;
  ops.ctx = hw;
  ops.now_us = hw_now;
  ops.sensor_request = hw_request;
  ops.sensor_poll = hw_poll;
  ops.arm_move = hw_move;
  ops.arm_read = hw_arm_read;
  ops.arm_stop = hw_stop;
  ops.gripper_open = hw_open;
  ops.gripper_close = hw_close;
  ops.gripper_read = hw_grip_read;
  return ops;
}

static void init_hw(fake_hw *hw, fg_task_config *tc) {
  /* One sensor only: close enough that neighbouring pixels land in touching voxels. */
  const float eye[3] = {0.5f, 0.05f, 0.6f}, target[3] = {0.5f, 0.f, 0.05f};
  const box3 narrow_x = {{0.475f, -0.06f, 0.f}, {0.525f, 0.06f, 0.10f}};
  memset(hw, 0, sizeof *hw);
  hw->t_us = 1000;
  hw->box = narrow_x;
  hw->contact_width = 0.05f;
  look_at(&hw->head, eye, target);
  CHECK_STATUS(fg_task_config_default(tc), FG_OK);
  tc->world_T_head = hw->head.pose;
  tc->use_hand = 0;
}

/* Steps at 125 Hz until the task ends (bounded: every state has a timeout). */
static fg_task_status run_task(fg_workspace *ws, fake_hw *hw) {
  fg_task_status st;
  int i;
  memset(&st, 0, sizeof st);
  for (i = 0; i < 100000; ++i) {
    CHECK_STATUS(fg_task_step(ws, &st), FG_OK);
    if (st.state == FG_TASK_SUCCEEDED || st.state == FG_TASK_FAILED) break;
    hw->t_us += 8000;
  }
  return st;
}

static void test_grasp_task(void) {
  fg_config cfg;
  fg_workspace *ws = NULL;
  fg_task_config tc;
  fake_hw hw;
  fg_hal_ops ops;
  fg_task_status st;
  small_config(&cfg);
  CHECK_STATUS(fg_init(g_mem_a, sizeof g_mem_a, &cfg, &ws), FG_OK);
  init_hw(&hw, &tc);
  ops = make_ops(&hw);
  /* Refusals. */
  CHECK_STATUS(fg_task_step(ws, &st), FG_ERR_INVALID_SEQUENCE);
  CHECK_STATUS(fg_task_abort(ws), FG_ERR_INVALID_SEQUENCE);
  CHECK_STATUS(fg_task_start(ws, NULL, &ops), FG_ERR_INVALID_ARGUMENT);
  CHECK_STATUS(fg_task_start(NULL, &tc, &ops), FG_ERR_NOT_A_WORKSPACE);
  ops.arm_stop = NULL;
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_ERR_INVALID_ARGUMENT);
  ops = make_ops(&hw);
  tc.struct_size = 8;
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_ERR_CONFIG_SIZE);
  tc.struct_size = sizeof tc;
  tc.speed_fraction = 2.0;
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_ERR_INVALID_CONFIG);
  tc.speed_fraction = 0.25;

  /* The whole grasp. */
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_OK);
  st = run_task(ws, &hw);
  CHECK(st.state == FG_TASK_SUCCEEDED);
  CHECK(st.failure == FG_TASK_OK);
  CHECK(hw.requests == 1 && hw.arm_moves == 8); /* start of the approach line, 6 steps along it, lift */
  CHECK(st.grasp.width_m > 0.04f && st.grasp.width_m < 0.06f);
  CHECK(fabs(st.q_lift[0] - hw.q[0]) < 1e-12 && fabs(st.q_lift[5] - hw.q[5]) < 1e-12);
  printf("task: %s after %u ticks, grasp width %.4f m, q_grasp %.3f %.3f %.3f %.3f %.3f %.3f: %s\n",
         st.state == FG_TASK_SUCCEEDED ? "succeeded" : "failed", st.ticks, st.grasp.width_m, st.q_grasp[0],
         st.q_grasp[1], st.q_grasp[2], st.q_grasp[3], st.q_grasp[4], st.q_grasp[5], fg_last_message(ws));

  /* Closing on nothing ends in FG_TASK_MISSED; an abort ends a running task. */
  init_hw(&hw, &tc);
  hw.contact_width = 0.f;
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_OK);
  st = run_task(ws, &hw);
  CHECK(st.state == FG_TASK_FAILED && st.failure == FG_TASK_MISSED);
  CHECK(fg_last_message(ws)[0] != '\0');
  init_hw(&hw, &tc);
  CHECK_STATUS(fg_task_start(ws, &tc, &ops), FG_OK);
  CHECK_STATUS(fg_task_step(ws, &st), FG_OK);
  CHECK_STATUS(fg_task_abort(ws), FG_OK);
  CHECK_STATUS(fg_task_step(ws, &st), FG_OK);
  CHECK(st.state == FG_TASK_FAILED && st.failure == FG_TASK_ABORTED && hw.stops == 1);
}

int main(void) {
  test_versions_and_sizes();
  test_status_strings();
  test_config();
  test_init_refusals();
  test_wrong_order_and_bad_arguments();
  test_plan_two_sensors();
  test_two_workspaces();
  test_grasp_task();
  if (g_failures != 0) {
    fprintf(stderr, "%d check(s) failed\n", g_failures);
    return 1;
  }
  printf("all C API checks passed\n");
  return 0;
}
