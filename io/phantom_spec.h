// The phantom specification SPEC.yaml read by `xsect phantom` (docs/inputs.md, phantoms), validated
// where it enters: every problem is an InputError naming the spec file, the key and the line.
//
// Format (lengths in mm, angles in degrees; keys in [] are optional, with their defaults):
//   [seed: 1]                       # non-negative integer: drives every random choice
//   shape:
//     kind: torus                   # sphere | ellipsoid | torus | genus2 | hollow_sphere |
//                                   # two_spheres | vessel_tree | twisted_cylinder | notched_torus | cup
//     params: {major_radius: 12, minor_radius: 4}   # per kind, see geometry/phantoms/phantom_shape.cpp
//     [centre: [0, 0, 0]]           # world position of the shape's origin, mm
//     [rotation_deg: [0, 0, 0]]     # xyz Euler angles: R = Rz * Ry * Rx
//     [label_split: {[point: [0, 0, 0]], normal: [1, 0, 0]}]   # two-label phantom (shape frame):
//                                   # label 1 where normal . (x - point) < 0, label 2 elsewhere;
//                                   # images hold the labels (0 background), no intensity
//                                   # degradations; config.yaml uses segmentation.method: labels
//   pattern:
//     kind: multiaxial              # parallel | multiaxial | random | fan | freehand
//     parallel:   count, [direction: [0,0,1]], [spacing_mm | span_mm], [positions_mm: [...]],
//                 [tilt_deg: 0]
//     multiaxial: count (per axis) | counts: [nx, ny, nz]
//     random:     count
//     fan:        count, [axis: [0,0,1]], [span_deg: 180]
//     freehand:   count, [direction: [0,0,1]], [span_mm], [tilt_deg: 3], [drift_mm: 1],
//                 [sector: false], [sector_angle_deg: auto], [apex_px: height / 4]
//     any kind:   [extra_planes: [{point: [x, y, z], normal: [nx, ny, nz]}, ...]]  # world frame:
//                 planes added after the pattern's, each imaged around the projection of the
//                 bounds' centre, or of its own [image_centre: [x, y, z]]
//   [image:]
//     [pixel_mm: auto]              # auto = bounding-sphere diameter / 160
//     [width: auto]                 # pixels, or auto = cover the bounding sphere's projection
//     [height: auto]
//     [margin_px: 4]
//   [degradations:]
//     [noise_sigma: 0]              # additive Gaussian noise, grey levels (of 255)
//     [speckle: 0]                  # std of the multiplicative speckle factor (1 + speckle*N(0,1))
//     [blur_sigma_px: 0]            # Gaussian blur, pixels
//     [pose_jitter_mm: 0]           # recorded pose error: translation std per axis, mm
//     [pose_jitter_deg: 0]          # recorded pose error: rotation std, degrees
//     [drop_probability: 0]         # probability that a frame is omitted from slices.yaml
//     [ultrasound: {[object_echo: 0.25], [grain_mm: 0.3], [reflectors: 2]}]   # B-mode look:
//                                   # tissue speckle (mean grey 100), the object hypoechoic
//                                   # (object_echo x the tissue's), per frame `reflectors` bright
//                                   # arcs whose shadows run to the far end of the beams, never
//                                   # over the object; beams from the sector's apex (or down the
//                                   # columns); speckle and blur_sigma_px are then not used
//   [config:]                       # merged into the generated config.yaml, nested maps or
//     reconstruction: {voxel_size_mm: 0.25}   # dotted keys ("reconstruction.voxel_size_mm: 0.25")
//   [plus: false]                   # also write the slices as a PLUS tracked-ultrasound recording:
//                                   # sequence.igs.mha (the same frames, zlib, MFA; per frame
//                                   # ProbeToTrackerTransform = recorded image_to_world with the
//                                   # pixel scaling removed, ReferenceToTrackerTransform = identity,
//                                   # statuses OK, Timestamp = 0.05 s x pattern index; dropped
//                                   # frames omitted as in slices.yaml), deviceset.xml (ImageToProbe
//                                   # = diag(pixel_mm, pixel_mm, pixel_mm, 1); a freehand sector is
//                                   # written as the PLUS fan FanAnglesDeg/FanOriginPixel/
//                                   # FanRadius*Pixel, the same mask as images/fov.png; no clip
//                                   # rectangle) and config_plus.yaml (config.yaml reading them)
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/phantoms/phantom_shape.h"
#include "geometry/phantoms/slicing_pattern.h"

namespace xsect {

/// An ultrasound-like appearance (issue 49): B-mode speckle, a hypoechoic object, bright
/// reflectors with their acoustic shadows (phantom_render.h renderUltrasoundSlice).
struct UltrasoundLook {
  bool enabled = false;
  double object_echo = 0.25;  ///< the object's echogenicity relative to the tissue's (hypoechoic < 1)
  double grain_mm = 0.3;      ///< speckle grain: correlation length of the echo field, mm
  int reflectors = 2;         ///< bright reflectors per frame, each casting a shadow to the far end
};

struct PhantomDegradations {
  UltrasoundLook ultrasound;
  double noise_sigma = 0.0;       ///< grey levels
  double speckle = 0.0;           ///< std of the multiplicative factor
  double blur_sigma_px = 0.0;     ///< pixels
  double pose_jitter_mm = 0.0;    ///< mm, per axis
  double pose_jitter_deg = 0.0;   ///< degrees
  double drop_probability = 0.0;  ///< [0, 1)
};

/// A plane through `point` with unit `normal` (world, mm).
struct PhantomPlane {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  /// The image is centred on this point's projection (default: the bounds' centre's): an image
  /// that sees only part of the object (issue 20, observed pieces).
  std::optional<Vec3> image_centre;
};

struct PhantomSpec {
  std::string path;                 ///< the spec file
  std::uint64_t seed = 1;
  PhantomShape shape;               ///< validated and completed (defaults, vessel tubes)
  SlicingPattern pattern;
  std::vector<PhantomPlane> extra_planes;  ///< pattern.extra_planes, after the pattern's planes
  ImageSpec image;                  ///< pixel_mm resolved (never auto)
  PhantomDegradations degradations;
  std::string config_yaml;          ///< the spec's `config:` map as YAML text ("{}" if absent)
  bool plus = false;                ///< `plus:` also write a PLUS recording (sequence.igs.mha, ...)
};

/// Reads and validates SPEC.yaml. Throws InputError (file, key, line).
PhantomSpec readPhantomSpec(const std::string& path);

}  // namespace xsect
