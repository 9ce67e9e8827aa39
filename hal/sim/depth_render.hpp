// Host-only simulation: depth images of a simulated world from a pinhole camera, with a
// structured-light (Xtion / Kinect v1 class) noise model, and their conversion to clouds.
#pragma once
#include <cstdint>
#include <vector>

#include "io/point_cloud.hpp"
#include "sim/sim_world.hpp"

namespace fg::sim {

struct Intrinsics {
  int width = 640;
  int height = 480;
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
};

//! A depth camera: intrinsics and world_T_sensor in the optical convention
//! (z forward, x right, y down).
struct Camera {
  Intrinsics K;
  Rigid world_T_sensor;
};

//! Sensor model. Validity limits (range, incidence) always apply; the random parts can be
//! switched off one by one.
struct NoiseModel {
  bool gaussian = true;  //!< axial noise sigma(z) = a + b (z - z0)^2 (Nguyen et al. 2012)
  double sigma_a = 1.2e-3;
  double sigma_b = 1.9e-3;
  double sigma_z0 = 0.4;
  bool quantize = true;             //!< disparity quantization: steps of k z^2 in depth
  double quant_k = 2.85e-3;         //!< = step of 1/z (1/m)
  double max_incidence_deg = 78.0;  //!< larger ray-to-normal angles give no return
  double z_min = 0.35;              //!< valid depth range (m)
  double z_max = 3.5;
  double edge_dropout = 0.25;  //!< probability of dropping a pixel next to a depth edge
  double edge_jump = 0.02;     //!< a neighbour this much nearer/farther (m) makes an edge
  int edge_band_px = 1;        //!< "next to": a neighbour up to this many pixels away along a row or column

  // Structured-light effects, off unless set (structured_light() sets them all); off, they
  // draw no random numbers, so the images of a model without them stay what they were.
  //! The projector sits projector_baseline (m) along the optical x axis: a surface point
  //! the projector cannot see (behind a nearer surface) gets no pattern, so no depth.
  bool projector_shadow = false;
  double projector_baseline = 0.075;
  //! Weak returns go missing: a pixel's return is albedo cos(incidence) / (z / 1 m)^2; it is
  //! dropped with probability 1 at return_none or below, falling linearly to 0 at return_full.
  bool dark_dropout = false;
  double return_none = 0.01;
  double return_full = 0.08;
  //! Steep surfaces thin out before max_incidence_deg: the dropout probability rises linearly
  //! from 0 at steep_from_deg to 1 at max_incidence_deg.
  bool steep_dropout = false;
  double steep_from_deg = 60.0;

  //! Only the validity limits: no random noise, no quantization, no dropouts.
  static NoiseModel none() {
    NoiseModel n;
    n.gaussian = false;
    n.quantize = false;
    n.edge_dropout = 0.0;
    return n;
  }

  //! The default model plus the structured-light effects: projector shadows, dark and steep
  //! surfaces thinning out, and dropouts up to 2 pixels from a depth edge.
  static NoiseModel structured_light() {
    NoiseModel n;
    n.edge_band_px = 2;
    n.projector_shadow = true;
    n.dark_dropout = true;
    n.steep_dropout = true;
    return n;
  }
};

//! Depth in millimetres, row-major, 0 = no return.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<uint16_t> mm;
  uint16_t at(int u, int v) const { return mm[static_cast<size_t>(v) * width + u]; }
};

//! Noise-free z depth (metres along the optical axis) of every pixel; NaN where no surface is
//! hit. No validity limits are applied. Optional per-pixel incidence cosine and hit object.
std::vector<double> render_true_depth(const World& world, const Camera& cam,
                                      std::vector<double>* cos_incidence = nullptr,
                                      std::vector<int>* hit_object = nullptr);

//! A simulated sensor frame: true depth, validity limits, then the noise model (seeded:
//! the same inputs give the same image on every run).
DepthImage render_depth(const World& world, const Camera& cam, const NoiseModel& noise, uint64_t seed);

//! Organized cloud (width x height) in the sensor optical frame; NaN for missing pixels.
fg::host::PointCloud depth_to_cloud(const DepthImage& depth, const Intrinsics& K);

//! Axial noise standard deviation of the model at depth z (m).
double depth_sigma(const NoiseModel& noise, double z);

}  // namespace fg::sim
