// config.yaml, the run configuration (docs/methods.md): read, overridden with --set key.path=value,
// validated, paths resolved against the file that names them. Unknown keys are input errors, with the
// key a typo was likely meant to be.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geometry/conformity/consensus_mode.h"
#include "geometry/conformity/pose_correction_kind.h"
#include "geometry/core/named_choice.h"
#include "geometry/core/plane_extent.h"
#include "geometry/core/reconstruction_method.h"
#include "geometry/delaunay/cell_tunnels.h"
#include "geometry/reconstruction/topology_goal.h"
#include "segmentation/segment_slice.h"

namespace xsect {

/// Where the sections come from: `input.<kind>` (exactly one).
enum class InputKind { slices, csl, contour, plus_sequence };
constexpr std::array<NamedChoice<InputKind>, 4> kInputKinds{{
    {InputKind::slices, "slices"},
    {InputKind::csl, "csl"},
    {InputKind::contour, "contour"},
    {InputKind::plus_sequence, "plus_sequence"},
}};

/// `smoothing.method`: the surface output besides the method's solid (docs/methods.md stage 6).
enum class SmoothingMethod { none, shepard, level_set };
constexpr std::array<NamedChoice<SmoothingMethod>, 3> kSmoothingMethods{{
    {SmoothingMethod::none, "none"},
    {SmoothingMethod::shepard, "shepard"},
    {SmoothingMethod::level_set, "level_set"},
}};

/// segmentation.preset: starting values for a kind of image, under the keys the configuration
/// leaves out (run_config.cpp applySegmentationPreset; docs/ultrasound.md).
enum class SegmentationPreset { none, ultrasound };
constexpr std::array<NamedChoice<SegmentationPreset>, 2> kSegmentationPresets{{
    {SegmentationPreset::none, "none"},
    {SegmentationPreset::ultrasound, "ultrasound"},
}};

struct RunConfig {
  std::string path;                 ///< the configuration file (absolute)
  // input (exactly one)
  InputKind input_kind = InputKind::slices;
  std::string input_path;           ///< resolved against the configuration file
  bool sections_in_memory = false;  ///< readRunConfigText's sections_given_as: no input file
  std::string plus_config_path;     ///< input.plus_config: the PLUS device-set XML (plus_sequence)
  /// input.reference_frame: the frame poses map into; empty: the device set's
  /// ReferenceCoordinateFrame, or `Reference`.
  std::string reference_frame;
  /// input.repair_contours: contours that cross themselves or each other are made simple
  /// (geometry/core/ring_repair.h) with a warning; false refuses them.
  bool repair_contours = true;
  /// input.plus_masks: a mask sequence (MetaImage) whose frames are the recording's, segmented
  /// instead of its grey frames (plus_sequence only); empty: none.
  std::string plus_masks_path;
  SegmentationParams segmentation;
  SegmentationPreset segmentation_preset = SegmentationPreset::none;
  /// Stage 3, conformity along plane intersections (geometry/conformity/conformity_enforcement.h).
  struct Conformity {
    bool enforce = false;             ///< edit the sections so that traces agree
    ConsensusMode mode = ConsensusMode::union_;
    double max_correction_mm = 5.0;   ///< larger corrections are reported, not applied
    double band_mm = 2.0;             ///< edits stay within this distance of their line
    double min_angle_deg = 5.0;       ///< pairs of planes at a smaller angle are not compared
    /// A slice whose median disagreement with the slices it crosses exceeds both this and 3 times
    /// the typical slice's is flagged.
    double flag_mm = 3.0;
    bool drop_flagged = false;        ///< flagged slices are left out of the reconstruction
    /// With pose correction: slices whose sections meet other slices' but whose every motion no
    /// crossing constrains (left at the recorded pose, with the tracker's error) are left out.
    bool drop_unplaced = true;
    /// With pose correction: slices whose sections still disagree with the slices they cross after
    /// the fit (pipeline/conform_stage.cpp, findUnreconciled) are left out.
    bool drop_unreconciled = true;
    /// Tracked sweeps: the poses are smoothed over this many frames on each side, in the slices'
    /// order (geometry/conformity/pose_smoothing.h); 0 = off.
    int pose_smoothing_frames = 0;
    /// Per-slice pose corrections estimated from the disagreement along the common lines
    /// (geometry/conformity/pose_correction.h), applied before the measurement.
    PoseCorrectionKind pose_correction = PoseCorrectionKind::none;
    /// The corrections' prior standard deviations (mm, degrees); empty = auto, from the
    /// disagreement measured on the recorded poses (any units).
    std::optional<double> pose_sigma_mm, pose_sigma_deg;
  } conformity;
  ReconstructionMethod reconstruction_method = ReconstructionMethod::nearest_plane;
  /// The voxel size, mm: the configuration's, or, when voxel_size_auto, 0 until the run resolves
  /// it from the sections (geometry/reconstruction/automatic_voxel_size.h).
  double voxel_size_mm = 0;
  bool voxel_size_auto = true;                          ///< `auto` (the default)
  std::int64_t voxel_budget = 4000000;                  ///< auto: the largest grid, voxels
  std::optional<double> end_margin_mm;                  ///< empty = auto
  /// `reconstruction.planes`: whether a slice cuts space only where it was observed (issue 20).
  /// Default (planes_default): observed for images and PLUS sequences with methods 1 and 2, else whole.
  PlaneExtent planes = PlaneExtent::whole;
  bool planes_default = true;
  bool conformal_mesh = true;  ///< cut the mesh along the planes onto the section contours
  /// `reconstruction.cell_tunnels` (method 3): cut tunnels of one cell's R'' that its sections do
  /// not carry (geometry/delaunay/cell_cycles.h), or keep the thesis' D3 as it is.
  CellTunnels cell_tunnels = CellTunnels::cut;
  /// `reconstruction.topology` and `reconstruction.min_feature_mm` (issue 51): free (the method's
  /// solid), simplest, or target Betti numbers; methods 1 and 2, without smoothing.
  TopologyGoal topology;
  SmoothingMethod smoothing_method = SmoothingMethod::none;
  double smoothing_exponent = 1.0;                      ///< Shepard: g(t) = t^p; +inf allowed
  std::optional<double> smoothing_cap_mm;               ///< Shepard: clamp of f_i; empty = auto
  double smoothing_adaptivity = 0.0;                    ///< OpenVDB mesh adaptivity in [0, 1]
  /// Shepard: when its solid joins the sections differently from the method's graph, output the
  /// level-set smoothing of the method's solid instead (which keeps that connectivity).
  bool smoothing_keep_connectivity = true;
  int smoothing_iterations = 8;                         ///< level_set: curvature-flow steps
  /// `sampling.*`: what the user knows of the object, for the sampling verdict (issue 18;
  /// geometry/sampling/sampling_conditions.h), and how many slices to advise.
  struct Sampling {
    std::optional<double> reach_mm;           ///< both reaches at once
    std::optional<double> reach_interior_mm;  ///< reach_i (overrides reach_mm)
    std::optional<double> reach_exterior_mm;  ///< reach_e (overrides reach_mm)
    std::optional<double> max_angle_deg;      ///< bound of α at contour points, [0, 90)
    std::optional<int> advice_count;          ///< empty: as many as the violated cells need
  } sampling;
  /// `run.max_seconds`: a run estimated to take longer is refused before its long stages, by
  /// `check` as by `run` (pipeline/time_budget.h). A day by default: a guard against settings that
  /// make the work explode, not a schedule.
  double max_seconds = 86400;
  std::string output_dir;           ///< resolved against the configuration file
  std::vector<std::string> mesh_formats{"ply"};
  std::vector<std::string> warnings;  ///< unknown keys and similar
  std::string resolved_yaml;        ///< the configuration after overrides, as YAML text
};

/// Every key a run configuration accepts, as dotted paths ("reconstruction.voxel_size_mm"), the
/// sections included ("reconstruction"): the list docs/configuration.md documents.
const std::set<std::string>& runConfigKeys();

/// @param overrides "key.path=value" strings; the value is parsed as YAML (number, bool, list...).
/// Throws InputError (file, key, line) on any invalid content.
RunConfig readRunConfig(const std::string& path, const std::vector<std::string>& overrides = {});

/// The same from YAML text (the Python module's configurations given as dicts). `path` names the
/// text in messages and need not exist; relative paths start from its folder. With
/// `sections_given_as` the configuration has no `input`: the sections come from the caller, read as
/// that kind of input's (csl: contours, slices: images), with no input_path.
RunConfig readRunConfigText(const std::string& text, const std::string& path,
                            const std::vector<std::string>& overrides = {},
                            std::optional<InputKind> sections_given_as = std::nullopt);

}  // namespace xsect
