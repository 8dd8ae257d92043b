"""xsect from Python: shapes from pose-tagged 2D sections, numpy in and out (docs/python.md).

    import xsect
    r = xsect.run("config.yaml")                       # as `xsect run config.yaml`, no files written
    r.betti, r.verdict, r.confidence                   # (1, 1, 0), 'violated', 'high'
    r.vertices, r.faces                                # float64 N x 3 (mm), int32 M x 3
    r.labels, r.affine                                 # uint16 volume [i, j, k], 4 x 4 (i, j, k, 1) -> mm
    r = xsect.run("config.yaml", out="result", reconstruction__method="delaunay")   # --set, --out

    r = xsect.reconstruct([{"pose": pose, "contours": [ring], "holes": []}, ...], method="section_voronoi")
    sections = xsect.slice(vertices, faces, [pose, ...])
    ph = xsect.phantom("spec.yaml", out="ph")          # as `xsect phantom`; ph.config to run

Settings are given as keyword arguments, a section's key joined to its section by two underscores
(reconstruction__voxel_size_mm=0.5), or as a dict `set={"reconstruction.voxel_size_mm": 0.5}`:
the same keys, checks and errors as `--set` (docs/configuration.md). Invalid input raises
xsect.InputError (a ValueError) with .file, .key and .line; the command line exits 2 on the same.
"""

import json as _json
import os as _os
import tempfile as _tempfile
from dataclasses import dataclass as _dataclass, field as _field

from . import _xsect

__version__ = _xsect.__version__
__all__ = ["run", "reconstruct", "slice", "phantom", "Result", "Phantom", "InputError"]

InputError = _xsect.InputError
InputError.__doc__ = "Invalid input: args are (message, file, key, line); the command line exits 2 on it."
InputError.__str__ = lambda self: str(self.args[0]) if self.args else ""
InputError.message = property(lambda self: self.args[0] if len(self.args) > 0 else "")
InputError.file = property(lambda self: self.args[1] if len(self.args) > 1 else "")
def _error_key(self):
    """The key: for a setting given as a keyword or in set= (which the command line names by its
    `--set key=value` option), its dotted name."""
    key = self.args[2] if len(self.args) > 2 else ""
    where = self.args[1] if len(self.args) > 1 else ""
    if not key and where.startswith("--set "):
        key = where[len("--set "):].split("=", 1)[0]
    return key


InputError.key = property(_error_key)
InputError.line = property(lambda self: self.args[3] if len(self.args) > 3 else -1)


@_dataclass
class Result:
    """A run's solid: its mesh, label volume and report (report.json as a dict)."""

    vertices: object  #: float64 N x 3, mm (mesh.ply's vertices)
    faces: object  #: int32 M x 3, indices into vertices, outward
    labels: object  #: uint16 volume, labels[i, j, k] (labels.nrrd)
    affine: object  #: float64 4 x 4: (i, j, k, 1) -> mm
    report: dict = _field(repr=False)  #: report.json
    out: str = None  #: the output folder, when one was written

    @property
    def mesh(self):
        """(vertices, faces)."""
        return self.vertices, self.faces

    @property
    def betti(self):
        """The solid's Betti numbers (components, tunnels, cavities)."""
        return tuple(self.report["betti"])

    @property
    def verdict(self):
        """The thesis' sampling verdict: satisfied, violated or undetermined (docs/topology.md)."""
        return self.report["sampling"]["verdict"]

    @property
    def confidence(self):
        """The topology's confidence: high, medium or low (docs/topology.md)."""
        return self.report["topology"]["confidence"]["level"]

    @property
    def in_plain_words(self):
        return self.report["in_plain_words"]


@_dataclass
class Phantom:
    """A phantom's folder (`xsect phantom`): its config.yaml runs it, truth.yaml evaluates it."""

    dir: str

    @property
    def config(self):
        return _os.path.join(self.dir, "config.yaml")

    @property
    def truth(self):
        return _os.path.join(self.dir, "truth.yaml")

    @property
    def slices(self):
        return _os.path.join(self.dir, "slices.yaml")


def _plain(value):
    """numpy arrays and scalars in a configuration dict, as JSON takes them."""
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"not a configuration value: {value!r}")


def _yaml_value(value):
    """A --set value: text as it is, anything else as JSON (which YAML reads)."""
    if isinstance(value, str):
        return value
    if hasattr(value, "tolist"):  # numpy arrays and scalars
        value = value.tolist()
    return _json.dumps(value)


def _overrides(settings, set_):
    out = []
    for key, value in (set_ or {}).items():
        out.append(f"{key}={_yaml_value(value)}")
    for key, value in settings.items():
        out.append(f"{key.replace('__', '.')}={_yaml_value(value)}")
    return out


def _progress(progress):
    if progress is None or progress is False or progress is True or callable(progress):
        return progress
    raise TypeError("progress must be None, True, False or a callable taking the stage's name")


def _result(d, out):
    return Result(vertices=d["vertices"], faces=d["faces"], labels=d["labels"], affine=d["affine"],
                  report=_json.loads(d["report"]), out=_os.path.abspath(out) if out else None)


def run(config, out=None, *, set=None, progress=None, threads=0, **settings):
    """`xsect run`: `config` a path to config.yaml or a dict of its keys (relative paths in a dict
    start from the current folder). Files are written only into `out` when it is given."""
    if isinstance(config, dict):
        name = _os.path.join(_os.getcwd(), "config (dict)")
        d = _xsect.run(name, _json.dumps(config, default=_plain), _os.fspath(out) if out else "",
                       _overrides(settings, set), _progress(progress), int(threads))
    else:
        d = _xsect.run(_os.fspath(config), "", _os.fspath(out) if out else "", _overrides(settings, set),
                       _progress(progress), int(threads))
    return _result(d, out)


def reconstruct(sections, method="nearest_plane", *, config=None, out=None, set=None, progress=None, threads=0,
                **settings):
    """Sections given in memory, no files read (and none written unless `out` is given).

    sections: a list of planes, each a dict with either
      pose      4 x 4: plane mm (x, y, 0, 1) -> world mm (first two columns unit and orthogonal)
      contours  list of N x 2 arrays, the outer rings of the plane's sections (plane mm)
      holes     list of N x 2 arrays, their holes (optional)
    (a plane without contours is an empty plane: it says the object is not there), or
      pose      4 x 4: pixel (i, j, 0, 1) -> world mm (columns scaled by the pixel spacing)
      mask      2D array, rows j and columns i, non-zero inside
    (segmented at 0.5 with the configuration's other segmentation settings; observed within the
    image's rectangle). Every plane of a call is of the same kind.
    method: nearest_plane (method 1), section_voronoi (method 2) or delaunay (method 3).
    config: a dict of configuration keys without `input` (e.g. {"smoothing": {"method": "shepard"}}).
    """
    import numpy as np

    planes = []
    for i, s in enumerate(sections):
        if not isinstance(s, dict) or "pose" not in s:
            raise InputError(f"sections[{i}] must be a dict with a pose and contours", "sections",
                             f"sections[{i}]", -1)
        rings = lambda key: [np.ascontiguousarray(r, dtype=np.float64).reshape(-1, 2) for r in s.get(key, [])]
        mask = s.get("mask")
        if mask is not None:
            mask = np.ascontiguousarray(np.asarray(mask) != 0, dtype=np.uint8)
        planes.append(_xsect._Plane(np.asarray(s["pose"], dtype=np.float64), rings("contours"), rings("holes"), mask))
    cfg = dict(config or {})
    cfg.setdefault("reconstruction", {})
    cfg["reconstruction"] = dict(cfg["reconstruction"], method=method)
    name = _os.path.join(_os.getcwd(), "sections (memory)")
    d = _xsect.reconstruct(planes, name, _json.dumps(cfg, default=_plain), _os.fspath(out) if out else "",
                           _overrides(settings, set), _progress(progress), int(threads))
    return _result(d, out)


def slice(vertices, faces, planes):
    """`xsect slice` in memory: the sections of a closed mesh on each plane (4 x 4 poses whose
    first two columns, normalised, are the plane's axes). Returns, per plane, a list of
    (outer, holes): N x 2 arrays in the plane's mm, holes a list of them."""
    import numpy as np

    return _xsect.slice(np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64),
                        [np.asarray(p, dtype=np.float64) for p in planes])


def phantom(spec, out, *, progress=False):
    """`xsect phantom`: `spec` a path to a phantom spec or a dict of its keys; writes the phantom's
    folder `out` (images, slices.yaml, config.yaml, truth.yaml) and returns it as a Phantom."""
    out = _os.path.abspath(_os.fspath(out))
    if isinstance(spec, dict):
        with _tempfile.TemporaryDirectory(prefix="xsect-spec-") as tmp:
            path = _os.path.join(tmp, "spec.yaml")
            with open(path, "w") as f:
                f.write(_json.dumps(spec))
            _xsect.phantom(path, out, not progress)
    else:
        _xsect.phantom(_os.fspath(spec), out, not progress)
    return Phantom(out)
