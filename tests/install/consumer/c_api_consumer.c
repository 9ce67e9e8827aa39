/* Uses the installed C API from C99, as firmware would: a 5 x 12 x 10 cm box on a table,
 * the head sensor's depth image and the hand sensor's points ray-cast here. Prints the
 * plan and "ok" when it found a grasp. */
#include <math.h>
#include <stdio.h>

#include "forcegrasp/forcegrasp.h"

#define W 160
#define H 120

typedef struct {
  float lo[3], hi[3];
} box3;

static FG_WORKSPACE_STORAGE(g_mem);
static uint16_t g_depth[W * H];
static float g_xyz[W * H * 3];

/* world_T_sensor of an optical frame at `eye` looking at `target` (x right, y down). */
static fg_pose look_at(const float eye[3], const float target[3]) {
  fg_pose p;
  float z[3], x[3], n;
  int i;
  for (i = 0; i < 3; ++i) z[i] = target[i] - eye[i];
  n = sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
  for (i = 0; i < 3; ++i) z[i] /= n;
  x[0] = z[1]; /* z x world up */
  x[1] = -z[0];
  x[2] = 0.f;
  n = sqrtf(x[0] * x[0] + x[1] * x[1]);
  if (n < 1e-6f) {
    x[0] = 1.f;
    x[1] = 0.f;
    n = 1.f;
  }
  x[0] /= n;
  x[1] /= n;
  for (i = 0; i < 3; ++i) {
    p.r[3 * i + 0] = x[i];
    p.r[3 * i + 2] = z[i];
    p.t[i] = eye[i];
  }
  p.r[1] = z[1] * x[2] - z[2] * x[1]; /* y = z x x */
  p.r[4] = z[2] * x[0] - z[0] * x[2];
  p.r[7] = z[0] * x[1] - z[1] * x[0];
  return p;
}

/* Depth along the ray's sensor z of the first hit (the table z = 0 or the box); 0: none. */
static float cast(const fg_pose *p, const float ray[3], const box3 *b) {
  float w[3], best, t0 = 0.f, t1 = 1e9f;
  int i, hit = 1;
  for (i = 0; i < 3; ++i) w[i] = p->r[3 * i] * ray[0] + p->r[3 * i + 1] * ray[1] + p->r[3 * i + 2] * ray[2];
  best = w[2] < -1e-6f ? -p->t[2] / w[2] : 1e9f;
  for (i = 0; i < 3 && hit; ++i) { /* slab test */
    if (fabsf(w[i]) < 1e-9f) {
      hit = p->t[i] >= b->lo[i] && p->t[i] <= b->hi[i];
    } else {
      float a = (b->lo[i] - p->t[i]) / w[i], c = (b->hi[i] - p->t[i]) / w[i];
      if (a > c) {
        const float s = a;
        a = c;
        c = s;
      }
      if (a > t0) t0 = a;
      if (c < t1) t1 = c;
      hit = t0 <= t1;
    }
  }
  if (hit && t0 > 0.f && t0 < best) best = t0;
  return best < 1e8f ? best : 0.f; /* the ray has z = 1: its parameter is the depth */
}

int main(void) {
  const box3 box = {{0.475f, -0.06f, 0.f}, {0.525f, 0.06f, 0.10f}};
  const float target[3] = {0.5f, 0.f, 0.05f}, head_eye[3] = {0.5f, 0.f, 0.9f}, hand_eye[3] = {0.5f, -0.45f, 0.45f};
  const fg_intrinsics k = {131.25f, 131.25f, 79.5f, 59.5f};
  const fg_pose head = look_at(head_eye, target), hand = look_at(hand_eye, target);
  fg_config cfg;
  fg_workspace *ws = NULL;
  fg_grasp g;
  fg_status s;
  size_t n = 0;
  int u, v;

  for (v = 0; v < H; ++v)
    for (u = 0; u < W; ++u) {
      const float ray[3] = {((float)u - k.cx) / k.fx, ((float)v - k.cy) / k.fy, 1.f};
      const float zh = cast(&head, ray, &box), zs = cast(&hand, ray, &box);
      g_depth[v * W + u] = (uint16_t)(zh > 0.f ? zh * 1000.f + 0.5f : 0.f);
      if (zs > 0.f) {
        g_xyz[3 * n + 0] = ray[0] * zs;
        g_xyz[3 * n + 1] = ray[1] * zs;
        g_xyz[3 * n + 2] = zs;
        ++n;
      }
    }

  s = fg_config_default(&cfg);
  cfg.crop_half_x_m = 0.25f; /* a small table patch */
  cfg.crop_half_y_m = 0.25f;
  if (s == FG_OK) s = fg_init(g_mem, sizeof g_mem, &cfg, &ws);
  if (s == FG_OK) s = fg_add_depth_image(ws, FG_SENSOR_HEAD, g_depth, W, H, &k, &head);
  if (s == FG_OK) s = fg_add_points(ws, FG_SENSOR_HAND, g_xyz, n, 3 * sizeof(float), &hand);
  if (s == FG_OK) s = fg_plan(ws, &g);
  printf("c api %u.%u.%u: %s (%s), %lu hand points\n", (unsigned)(fg_version() >> 16),
         (unsigned)(fg_version() >> 8 & 0xffu), (unsigned)(fg_version() & 0xffu), fg_status_str(s),
         ws ? fg_last_message(ws) : "", (unsigned long)n);
  if (s != FG_OK) return 1;
  printf("grasp: position %.3f %.3f %.3f approach %.2f %.2f %.2f width %.3f\n", g.position[0], g.position[1],
         g.position[2], g.approach[0], g.approach[1], g.approach[2], g.width_m);
  printf("ok\n");
  return 0;
}
