// Rendering of one phantom slice (docs/inputs.md, phantoms): the image an ideal scanner would record on
// a plane through an analytic shape, then the degradations of real data. A pixel (i, j) at world
// point p gets I = clamp(127.5 * (1 - sdf(p) / pixel_mm), 0, 255): an anti-aliased edge whose
// 127.5 iso-line is the section boundary sdf = 0 (exactly, before degradations and rounding).
// Two-label phantoms are rendered as label images instead: pixel = material label at p (0, 1, 2).
#pragma once

#include <cstdint>
#include <optional>
#include <opencv2/core.hpp>

#include "geometry/phantoms/phantom_shape.h"
#include "geometry/phantoms/slicing_pattern.h"
#include "io/phantom_spec.h"

namespace xsect {

struct RenderedSlice {
  cv::Mat image;         ///< CV_8UC1, height x width
  bool clipped = false;  ///< part of the section lies outside the image or field of view
};

/// @param shape    the phantom (world placement included)
/// @param pose     true image_to_world (docs/inputs.md convention); pixel size = norm of column 0, mm
/// @param width    image size, pixels
/// @param height
/// @param fov      empty, or CV_8UC1 height x width mask: pixels where it is 0 are set to 0
/// @param degr     noise (grey levels), speckle (relative), blur (pixels); poses are not touched
/// @param seed     phantom seed; the slice's noise stream is derived from (seed, index)
/// @param index    slice index
/// Deterministic: rows are rendered in parallel (TBB) but each pixel depends only on its
/// position; random numbers are drawn sequentially from the slice's own std::mt19937_64.
RenderedSlice renderSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                          const cv::Mat& fov, const PhantomDegradations& degr, std::uint64_t seed,
                          int index);

/// The B-mode image of a slice (degr.ultrasound enabled): the echogenicity is the tissue's (1)
/// outside the object and object_echo inside (anti-aliased over a pixel at sdf = 0), times a
/// Rayleigh speckle of grain grain_mm (the modulus of a complex Gaussian field smoothed to that
/// correlation length, unit mean), scaled to a tissue mean of grey 100. Each frame gets
/// `reflectors` bright arcs (echo 3, 3 pixels thick, across a tenth of the beams) in the upper half
/// of the view, each darkening everything beyond it along its beams to 5% (an acoustic shadow to
/// the far end); an arc is placed only where neither it nor its shadow comes within 2 pixels of
/// the object (up to 30 tries). Beams are rays from the sector's apex, or the columns when the
/// frame has no sector. Then additive noise (noise_sigma) and the field of view. `clipped` as
/// renderSlice's. Deterministic as renderSlice.
RenderedSlice renderUltrasoundSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                                    const cv::Mat& fov, const std::optional<SectorFov>& sector,
                                    const PhantomDegradations& degr, std::uint64_t seed, int index);

/// The label image of a slice: CV_8UC1, pixel (i, j) = materialLabel(shape, p) at its centre p
/// (0 background, 1 and 2 the materials of a label_split), 0 where `fov` is 0. No anti-aliasing
/// and no degradations. Deterministic.
RenderedSlice renderLabelSlice(const PhantomShape& shape, const Mat4& pose, int width, int height,
                               const cv::Mat& fov);

/// CV_8UC1 mask (255 inside the sector) of a fan-shaped field of view.
cv::Mat sectorMask(const SectorFov& sector, int width, int height);

/// The recorded pose of slice `index`: the true pose moved by a random rigid motion about the
/// image centre (rotation ~ N(0, jitter_deg) about a random axis, translation ~ N(0, jitter_mm)
/// per world axis), as a tracker error would. Returns `pose` unchanged when both are 0.
Mat4 jitterPose(const Mat4& pose, int width, int height, double jitter_mm, double jitter_deg,
                std::uint64_t seed, int index);

/// Whether frame `index` is dropped (probability p), from its own random stream.
bool dropFrame(double p, std::uint64_t seed, int index);

}  // namespace xsect
