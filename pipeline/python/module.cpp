// The Python module `xsect` (issue 55; docs/python.md): the same stages as `xsect run`
// (pipeline/run_stages.h) and the same phantoms and cuts as `xsect phantom` and `xsect slice`,
// with numpy arrays in and out. This file is the compiled part, `xsect._xsect`; the package's
// __init__.py (pipeline/python/xsect/) gives it its Python face (Result, keyword settings, dicts).
//
// The GIL is released while the stages run (their TBB loops use every allowed core); a progress
// callback takes it back for the moment of its call. Invalid input raises xsect.InputError (a
// ValueError) whose args are (message, file, key, line): the errors the command line exits 2 with.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/global_control.h>

#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/core/plane_of_pose.h"
#include "geometry/core/polygon.h"
#include "geometry/meshing/mesh_topology.h"
#include "geometry/slicing/mesh_sections.h"
#include "io/input_error.h"
#include "pipeline/commands.h"
#include "pipeline/input_stage.h"
#include "pipeline/load_sections.h"
#include "pipeline/run_outputs.h"
#include "pipeline/run_stages.h"

namespace py = pybind11;

namespace xsect {
namespace {

/// What a run hands back, copied out of the stages while they exist (without the GIL).
struct Outcome {
  std::vector<double> vertices;       ///< N x 3, mm
  std::vector<std::int32_t> faces;    ///< M x 3
  std::vector<std::uint16_t> labels;  ///< labels.nrrd's voxels, x fastest
  GridSpec grid;                      ///< their grid
  std::string report;                 ///< report.json
};

Outcome outcomeOf(const RunResults& r, StageClock& clock, const RunOptions& o) {
  Outcome out;
  const TriangleMesh& m = r.meshes.mesh;
  out.vertices.reserve(3 * m.vertices.size());
  for (const auto& v : m.vertices)
    for (int a = 0; a < 3; ++a) out.vertices.push_back(double(v[a]));
  out.faces.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (int a = 0; a < 3; ++a) out.faces.push_back(std::int32_t(t[std::size_t(a)]));
  out.grid = r.meshes.voxel_label.grid();
  out.labels = denseValues(r.meshes.voxel_label);
  out.report = (o.out.empty() ? reportJson(r, clock) : writeRunOutputs(r, o, clock)).dump();
  return out;
}

/// Progress on stderr when `progress` is True, through `progress(stage)` when it is callable,
/// none when it is None or False.
struct PythonProgress {
  explicit PythonProgress(const py::object& progress) {
    const bool callable = !progress.is_none() && PyCallable_Check(progress.ptr());
    const bool printed = !callable && PyObject_IsTrue(progress.ptr()) == 1;
    progress_ = std::make_unique<Progress>(!printed);
    if (callable) {
      callback_ = progress;
      progress_->onStage([this](const std::string& stage) {
        py::gil_scoped_acquire gil;
        callback_(stage);
      });
    }
  }
  PythonProgress(const PythonProgress&) = delete;
  PythonProgress& operator=(const PythonProgress&) = delete;
  std::unique_ptr<Progress> progress_;
  py::object callback_;
};

/// TBB's limit for the call: 0 = every core.
std::unique_ptr<tbb::global_control> threadLimit(int threads) {
  if (threads < 0) throw InputError("", "threads", "must be >= 0 (0 = every core)");
  return threads > 0 ? std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads)
                     : nullptr;
}

/// A vector handed to numpy without a copy: the array owns it through a capsule (a 2000-frame
/// sweep's labels are 143 MB; a copy would hold them twice).
template <typename T>
py::array_t<T> arrayOwning(std::vector<T>&& values, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides) {
  auto* owned = new std::vector<T>(std::move(values));
  const py::capsule owner(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), std::move(strides), owned->data(), owner);
}

py::dict toPython(Outcome&& o) {
  const py::ssize_t nv = py::ssize_t(o.vertices.size() / 3), nf = py::ssize_t(o.faces.size() / 3);
  const py::ssize_t d = sizeof(double), i = sizeof(std::int32_t), u = sizeof(std::uint16_t);
  py::array_t<double> vertices = arrayOwning(std::move(o.vertices), {nv, 3}, {3 * d, d});
  py::array_t<std::int32_t> faces = arrayOwning(std::move(o.faces), {nf, 3}, {3 * i, i});
  // labels[i, j, k] is voxel (i, j, k): x fastest in memory (Fortran order), as nibabel and
  // SimpleITK's arrays of an (i, j, k) affine read them.
  const auto& n = o.grid.dims;
  py::array_t<std::uint16_t> labels = arrayOwning(std::move(o.labels), {n[0], n[1], n[2]},
                                                  {u, u * n[0], u * n[0] * py::ssize_t(n[1])});
  py::array_t<double> affine({py::ssize_t(4), py::ssize_t(4)});
  auto A = affine.mutable_unchecked<2>();
  for (py::ssize_t r = 0; r < 4; ++r)
    for (py::ssize_t c = 0; c < 4; ++c) A(r, c) = r == c ? (r < 3 ? o.grid.voxel : 1.0) : 0.0;
  for (py::ssize_t r = 0; r < 3; ++r) A(r, 3) = o.grid.origin[r];
  py::dict out;
  out["vertices"] = vertices;
  out["faces"] = faces;
  out["labels"] = labels;
  out["affine"] = affine;
  out["report"] = std::move(o.report);
  return out;
}

RunOptions optionsOf(const std::string& config, const std::string& config_text, const std::string& out,
                     const std::vector<std::string>& overrides) {
  RunOptions o;
  o.config = config;
  o.config_text = config_text;
  o.out = out;
  o.overrides = overrides;
  return o;
}

/// The stages `start` runs (handing their results to the consumer it is given), without the GIL,
/// their results copied into arrays.
py::dict stagesToPython(const RunOptions& o, const py::object& progress, int threads,
                        const std::function<void(Progress&, const RunConsumer&)>& start) {
  PythonProgress p(progress);
  Outcome outcome;
  {
    py::gil_scoped_release release;
    const auto limit = threadLimit(threads);
    start(*p.progress_, [&](const RunResults& r, StageClock& clock) { outcome = outcomeOf(r, clock, o); });
    p.progress_->finish();
  }
  return toPython(std::move(outcome));
}

/// xsect._xsect.run: a configuration read from `config` (a path), or from `config_text` (its
/// YAML; `config` then names it and is the folder relative paths start from).
py::dict run(const std::string& config, const std::string& config_text, const std::string& out,
             const std::vector<std::string>& overrides, const py::object& progress, int threads) {
  const RunOptions o = optionsOf(config, config_text, out, overrides);
  return stagesToPython(o, progress, threads,
                        [&](Progress& p, const RunConsumer& consume) { runStages(o, p, consume); });
}

using Ring2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// One plane of sections given in memory: its pose and either the outer rings and holes of its
/// sections, in plane mm (pose: plane mm (x, y, 0, 1) -> world mm), or a mask (pose: pixel
/// (i, j, 0, 1) -> world mm, as slices.yaml's image_to_world).
struct GivenPlane {
  Eigen::Matrix4d pose;
  std::vector<Ring2> outers, holes;
  std::optional<py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>> mask;
};

PosedMask posedMaskOf(const GivenPlane& g, std::size_t index) {
  const std::string key = "sections[" + std::to_string(index) + "]";
  if (!g.pose.allFinite()) throw InputError("sections", key + ".pose", "must hold finite numbers");
  if (const std::string problem = poseProblem(g.pose); !problem.empty())
    throw InputError("sections", key + ".pose", problem);
  if (!g.outers.empty() || !g.holes.empty())
    throw InputError("sections", key, "give contours or a mask, not both");
  const auto& m = *g.mask;
  if (m.ndim() != 2 || m.shape(0) < 2 || m.shape(1) < 2)
    throw InputError("sections", key + ".mask", "must be a 2D array of at least 2 x 2 pixels (rows j, columns i)");
  PosedMask out;
  out.image_to_world = g.pose;
  out.mask = cv::Mat(int(m.shape(0)), int(m.shape(1)), CV_8U);
  std::memcpy(out.mask.data, m.data(), std::size_t(m.size()));
  return out;
}

CuttingPlane cuttingPlaneOf(const GivenPlane& g, std::size_t index) {
  const std::string key = "sections[" + std::to_string(index) + "]";
  if (!g.pose.allFinite()) throw InputError("sections", key + ".pose", "must hold finite numbers");
  if (const std::string problem = poseProblem(g.pose); !problem.empty())
    throw InputError("sections", key + ".pose", problem);
  Vec2 spacing;
  CuttingPlane cp;
  cp.plane = planeOfPose(g.pose, &spacing);
  if (std::abs(spacing.x() - 1) > 1e-6 || std::abs(spacing.y() - 1) > 1e-6)
    throw InputError("sections", key + ".pose",
                     "its first two columns must be unit vectors (contours are in plane mm), not of lengths " +
                         std::to_string(spacing.x()) + " and " + std::to_string(spacing.y()));
  cp.name = "plane " + std::to_string(index + 1);
  const auto rings = [&](const std::vector<Ring2>& given, const char* what) {
    std::vector<Ring> out;
    for (std::size_t r = 0; r < given.size(); ++r) {
      const Ring2& m = given[r];
      if (m.rows() < 3 || !m.allFinite())
        throw InputError("sections", key + "." + what + "[" + std::to_string(r) + "]",
                         "must be a ring of at least 3 finite points (N x 2, plane mm)");
      Ring ring;
      for (Eigen::Index i = 0; i < m.rows(); ++i) ring.emplace_back(m(i, 0), m(i, 1));
      out.push_back(std::move(ring));
    }
    return out;
  };
  cp.sections = sectionsFromRings(rings(g.outers, "contours"), rings(g.holes, "holes"));
  cp.observed_everywhere = true;  // as a contour file: all of O ∩ P on each plane
  cp.extent = sectionBounds(cp.sections);
  return cp;
}

/// xsect._xsect.reconstruct: sections given in memory, the configuration's YAML without `input`.
py::dict reconstruct(const std::vector<GivenPlane>& planes, const std::string& name, const std::string& config_text,
                     const std::string& out, const std::vector<std::string>& overrides, const py::object& progress,
                     int threads) {
  if (planes.empty()) throw InputError("sections", "sections", "at least one plane is required");
  SectionsInMemory given;
  for (std::size_t p = 0; p < planes.size(); ++p) {
    if (planes[p].mask) given.masks.push_back(posedMaskOf(planes[p], p));
    else given.contours.push_back(cuttingPlaneOf(planes[p], p));
  }
  const RunOptions o = optionsOf(name, config_text, out, overrides);
  return stagesToPython(o, progress, threads, [&](Progress& p, const RunConsumer& consume) {
    StageClock clock;
    const RunInputs in = inputsFromSections(o, std::move(given), clock, p);
    runStages(in, p, clock, consume);
  });
}

/// xsect._xsect.slice: the sections of a closed mesh on planes given by their poses; per plane a
/// list of (outer ring, [holes]) as N x 2 arrays in plane mm.
py::list slice(const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& vertices,
               const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
               const std::vector<Eigen::Matrix4d>& poses) {
  TriangleMesh mesh;
  if (!vertices.allFinite()) throw InputError("mesh", "vertices", "must be finite");
  for (Eigen::Index i = 0; i < vertices.rows(); ++i)
    mesh.vertices.emplace_back(float(vertices(i, 0)), float(vertices(i, 1)), float(vertices(i, 2)));
  for (Eigen::Index t = 0; t < faces.rows(); ++t) {
    std::array<std::uint32_t, 3> tri{};
    for (int a = 0; a < 3; ++a) {
      if (faces(t, a) < 0 || faces(t, a) >= vertices.rows())
        throw InputError("mesh", "faces[" + std::to_string(t) + "]", "refers to no vertex");
      tri[std::size_t(a)] = std::uint32_t(faces(t, a));
    }
    mesh.triangles.push_back(tri);
  }
  if (mesh.triangles.empty()) throw InputError("mesh", "faces", "holds no triangle");
  if (!meshTopology(mesh).watertight)  // as `xsect slice`
    throw InputError("mesh", "faces", "the mesh is not closed (an edge not shared by exactly two triangles): it bounds no solid to cut");
  std::vector<std::vector<Section>> cut(poses.size());
  for (std::size_t p = 0; p < poses.size(); ++p) {
    const std::string key = "planes[" + std::to_string(p) + "]";
    if (const std::string problem = poseProblem(poses[p]); !problem.empty()) throw InputError("planes", key, problem);
  }
  {
    py::gil_scoped_release release;
    for (std::size_t p = 0; p < poses.size(); ++p) {
      try {
        cut[p] = meshSections(mesh, planeOfPose(poses[p]));
      } catch (const std::invalid_argument& e) {
        throw InputError("mesh", "mesh", std::string(e.what()) + " (planes[" + std::to_string(p) + "])");
      }
    }
  }
  const auto array = [](const Ring& r) {
    py::array_t<double> a({py::ssize_t(r.size()), py::ssize_t(2)});
    auto A = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < r.size(); ++i) A(py::ssize_t(i), 0) = r[i].x(), A(py::ssize_t(i), 1) = r[i].y();
    return a;
  };
  py::list out;
  for (const auto& sections : cut) {
    py::list plane;
    for (const Section& s : sections) {
      py::list holes;
      for (const Ring& h : s.holes) holes.append(array(h));
      plane.append(py::make_tuple(array(s.outer), holes));
    }
    out.append(plane);
  }
  return out;
}

/// xsect._xsect.phantom: `xsect phantom SPEC --out OUT`.
void phantom(const std::string& spec, const std::string& out, bool quiet) {
  PhantomOptions o;
  o.spec = spec;
  o.out = out;
  o.quiet = quiet;
  py::gil_scoped_release release;
  phantomCommand(o);
}

}  // namespace
}  // namespace xsect

PYBIND11_MODULE(_xsect, m) {
  using namespace xsect;
  m.doc() = "xsect's compiled part; use the package xsect (docs/python.md).";
  m.attr("__version__") = XSECT_VERSION;
  static py::exception<InputError> inputError(m, "InputError", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      const py::tuple args = py::make_tuple(std::string(e.what()), e.file(), e.field(), e.line());
      PyErr_SetObject(inputError.ptr(), args.ptr());
    }
  });
  py::class_<GivenPlane>(m, "_Plane")
      .def(py::init([](const Eigen::Matrix4d& pose, std::vector<Ring2> outers, std::vector<Ring2> holes,
                       std::optional<py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>> mask) {
             return GivenPlane{pose, std::move(outers), std::move(holes), std::move(mask)};
           }),
           py::arg("pose"), py::arg("outers"), py::arg("holes"), py::arg("mask") = py::none());
  m.def("run", &run, py::arg("config"), py::arg("config_text"), py::arg("out"), py::arg("overrides"),
        py::arg("progress"), py::arg("threads"));
  m.def("reconstruct", &reconstruct, py::arg("planes"), py::arg("name"), py::arg("config_text"), py::arg("out"),
        py::arg("overrides"), py::arg("progress"), py::arg("threads"));
  m.def("slice", &slice, py::arg("vertices"), py::arg("faces"), py::arg("poses"));
  m.def("phantom", &phantom, py::arg("spec"), py::arg("out"), py::arg("quiet"));
}
