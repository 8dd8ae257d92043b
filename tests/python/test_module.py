"""The Python module `xsect` (issue 55, docs/python.md), run by ctest (PythonModule) with
PYTHONPATH at the build's python/ folder and XSECT_BIN the command-line tool: the module must give
what the command line gives, numpy in and out, write nothing unless asked, and raise InputError
where the tool exits 2."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import xsect

XSECT_BIN = os.environ.get("XSECT_BIN", "xsect")

# A torus (R = 12, r = 4 mm) cut by three stacks of 6 planes: small enough to run in a second.
TORUS = {
    "seed": 3,
    "shape": {"kind": "torus", "params": {"major_radius": 12, "minor_radius": 4}, "rotation_deg": [20, 10, 0]},
    "pattern": {"kind": "multiaxial", "count": 8},
    "image": {"pixel_mm": 0.4},
    "config": {"reconstruction": {"voxel_size_mm": 0.6}},
}


@pytest.fixture(scope="module")
def torus(tmp_path_factory):
    return xsect.phantom(TORUS, tmp_path_factory.mktemp("ph") / "torus")


def mesh_volume(vertices, faces):
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def ply_vertices(path):
    """mesh.ply's vertices (binary little-endian float32 x, y, z first)."""
    data = open(path, "rb").read()
    head = data[: data.index(b"end_header\n") + len(b"end_header\n")].decode()
    n = int(next(l.split()[2] for l in head.splitlines() if l.startswith("element vertex")))
    props = [l.split()[-1] for l in head.splitlines() if l.startswith("property") and "list" not in l]
    assert props[:3] == ["x", "y", "z"], head
    stride = 4 * len(props)
    raw = np.frombuffer(data[len(head): len(head) + n * stride], dtype="<f4").reshape(n, len(props))
    return raw[:, :3].astype(np.float64)


def test_run_gives_the_command_lines_solid_and_writes_nothing_unless_asked(torus, tmp_path):
    before = sorted(os.listdir(torus.dir))
    r = xsect.run(torus.config)
    assert sorted(os.listdir(torus.dir)) == before  # no output folder made
    assert r.out is None
    assert r.betti == (1, 1, 0)  # the truth's
    assert r.verdict in ("satisfied", "violated", "undetermined")
    assert r.confidence in ("high", "medium", "low")
    assert r.vertices.dtype == np.float64 and r.vertices.shape[1] == 3
    assert r.faces.dtype == np.int32 and r.faces.shape[1] == 3
    assert r.faces.min() >= 0 and r.faces.max() < len(r.vertices)
    # The command line's run of the same configuration: the same mesh, the same report's topology.
    out = tmp_path / "cli"
    subprocess.run([XSECT_BIN, "run", torus.config, "--out", str(out), "--quiet"], check=True,
                   stdout=subprocess.DEVNULL)
    np.testing.assert_array_equal(ply_vertices(out / "mesh.ply"), r.vertices.astype(np.float32).astype(np.float64))
    report = json.load(open(out / "report.json"))
    assert tuple(report["betti"]) == r.betti
    assert report["sampling"]["verdict"] == r.verdict
    # One solid: the label volume holds the mesh's volume (within the voxels cut by the surface).
    voxel = r.affine[0, 0]
    assert r.labels.dtype == np.uint16 and r.labels.ndim == 3
    assert r.labels.flags["F_CONTIGUOUS"]  # x fastest, as labels.nrrd
    labelled = float((r.labels > 0).sum()) * voxel ** 3
    volume = mesh_volume(r.vertices, r.faces)
    assert volume == pytest.approx(2 * math.pi ** 2 * 12 * 4 ** 2, rel=0.06)
    assert labelled == pytest.approx(volume, rel=0.04)
    # The affine places voxel (i, j, k): the centre of the torus' tube is inside, its hole's centre not.
    inv = np.linalg.inv(r.affine)
    def label_at(p):
        i, j, k, _ = np.rint(inv @ np.append(p, 1.0)).astype(int)
        return r.labels[i, j, k]
    mean = r.vertices.mean(axis=0)
    assert label_at(mean) == 0  # the hole
    inner_wall = r.vertices[np.argmin(np.linalg.norm(r.vertices - mean, axis=1))]
    outward = (inner_wall - mean) / np.linalg.norm(inner_wall - mean)
    assert label_at(inner_wall + 4.0 * outward) == 1  # 4 mm past the inner wall: the tube's centre


UNREPEATABLE = {"timings_s", "peak_memory_mb", "throughput", "evaluate_s", "voxels_per_s", "threads", "search_s"}


def comparable(path, folder):
    """A file of a run's folder as two runs of the same inputs give it alike: every file byte for
    byte but report.json, manifest.json (without times, memory and the thread count) and
    report.html (without its block of times), with the folder's own path taken out."""
    name = os.path.basename(path)
    if name in ("report.json", "manifest.json"):
        def strip(v):
            if isinstance(v, dict):
                return {k: strip(x) for k, x in v.items() if k not in UNREPEATABLE}
            return [strip(x) for x in v] if isinstance(v, list) else v
        return json.dumps(strip(json.load(open(path))), sort_keys=True).replace(str(folder), "<out>").encode()
    if name == "report.html":
        text = open(path, encoding="utf-8").read()
        a, b = text.find("<!--xsect-unrepeatable-begin-->"), text.find("<!--xsect-unrepeatable-end-->")
        return (text[:a] + text[b:] if 0 <= a < b else text).replace(str(folder), "<out>").encode()
    return open(path, "rb").read()


def test_run_with_out_writes_the_command_lines_files_byte_for_byte(torus, tmp_path):
    cli, py = tmp_path / "cli", tmp_path / "py"
    subprocess.run([XSECT_BIN, "run", torus.config, "--out", str(cli), "--quiet", "--set", "smoothing.method=shepard"],
                   check=True, stdout=subprocess.DEVNULL)
    r = xsect.run(torus.config, out=py, smoothing__method="shepard")
    names = sorted(os.listdir(cli))
    assert names == sorted(os.listdir(py))
    assert {"mesh.ply", "labels.nrrd", "level_set.vdb", "graph.json", "report.json", "report.html"} <= set(names)
    for name in names:
        assert comparable(cli / name, cli) == comparable(py / name, py), name
    assert r.betti == tuple(json.load(open(py / "report.json"))["betti"])


def test_run_writes_the_output_folder_when_asked_and_settings_act(torus, tmp_path):
    out = tmp_path / "m2"
    r = xsect.run(torus.config, out=out, reconstruction__method="section_voronoi")
    assert r.out == str(out)
    assert (out / "report.json").exists() and (out / "mesh.ply").exists() and (out / "labels.nrrd").exists()
    assert r.report["reconstruction"]["method"] == "section_voronoi"
    assert json.load(open(out / "report.json"))["betti"] == list(r.betti)
    same = xsect.run(torus.config, set={"reconstruction.method": "section_voronoi"})
    np.testing.assert_array_equal(same.vertices, r.vertices)


def test_a_dict_configuration_and_one_thread_give_the_same_arrays(torus):
    by_path = xsect.run(torus.config)
    config = {"input": {"slices": torus.slices}, "reconstruction": {"voxel_size_mm": 0.6}}
    by_dict = xsect.run(config, threads=1)
    np.testing.assert_array_equal(by_dict.vertices, by_path.vertices)
    np.testing.assert_array_equal(by_dict.faces, by_path.faces)
    np.testing.assert_array_equal(by_dict.labels, by_path.labels)


def test_errors_are_input_errors_with_file_key_and_line(torus, tmp_path):
    with pytest.raises(xsect.InputError) as e:
        xsect.run(torus.config, reconstruction__voxle_size_mm=0.5)
    assert isinstance(e.value, ValueError)
    assert "reconstruction.voxel_size_mm" in str(e.value)  # the did-you-mean
    with pytest.raises(xsect.InputError) as e:
        xsect.run(torus.config, reconstruction__voxel_size_mm=-1)
    assert e.value.key == "reconstruction.voxel_size_mm"
    bad = tmp_path / "bad.yaml"
    bad.write_text("input:\n  slices: missing.yaml\n")
    with pytest.raises(xsect.InputError) as e:
        xsect.run(bad)
    assert e.value.file == str(bad) and e.value.key == "input.slices" and e.value.line == 2
    with pytest.raises(xsect.InputError):
        xsect.run(torus.config, out=torus.dir)  # the input's own folder: refused, nothing touched


def torus_sections(planes=24, R=12.0, r=4.0):
    """Analytic sections of the torus (x² + y² + z² + R² - r²)² = 4R²(x² + y²) on planes z = c:
    annuli (two circles), the inner one a hole."""
    out = []
    for c in np.linspace(-r, r, planes + 2)[1:-1]:
        w = math.sqrt(r * r - c * c)
        t = np.linspace(0, 2 * math.pi, 200, endpoint=False)
        circle = lambda rad: np.c_[rad * np.cos(t), rad * np.sin(t)]
        pose = np.eye(4)
        pose[2, 3] = c
        out.append({"pose": pose, "contours": [circle(R + w)], "holes": [circle(R - w)[::-1]]})
    return out


def test_reconstruct_from_sections_in_memory_gives_the_torus(tmp_path):
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for method in ("nearest_plane", "section_voronoi"):
            r = xsect.reconstruct(torus_sections(), method=method, reconstruction__voxel_size_mm=0.4)
            assert r.betti == (1, 1, 0), method
            assert r.report["reconstruction"]["method"] == method
        assert os.listdir(tmp_path) == []  # no files at all
    finally:
        os.chdir(cwd)
    # A pose whose axes are not unit (pixels, not mm) is refused with the plane named.
    bad = torus_sections(3)
    bad[1]["pose"] = np.diag([0.5, 0.5, 1.0, 1.0])
    with pytest.raises(xsect.InputError) as e:
        xsect.reconstruct(bad)
    assert e.value.key == "sections[1].pose"


def symmetric_circle(radius, n=128):
    """A circle's ring with coordinates on a 1/64 mm lattice and point-symmetric (p and -p both in
    it): its vertices' mean is exactly 0 in any order of summation."""
    t = np.arange(n // 2) * (2 * math.pi / n)
    half = np.round(np.c_[radius * np.cos(t), radius * np.sin(t)] * 64) / 64
    return np.r_[half, -half]


def test_reconstruct_from_contours_equals_the_csl_route(tmp_path):
    # Annuli of the torus on planes z = c, written as a .csl and given in memory in the frame a
    # .csl's plane gets (u = n x e_x = (0, 1, 0), v = (-1, 0, 0), origin the vertices' mean: 0).
    lines = []
    given = []
    zs = [-3.5 + 0.5 * k for k in range(15)]
    for p, c in enumerate(zs):
        w = math.sqrt(16 - c * c)
        rings = [symmetric_circle(12 + w), symmetric_circle(12 - w)]
        count = sum(len(r) for r in rings)
        lines += [f"{p + 1} {count} 2 0 0 1 {-c!r}", ""]
        lines += [f"{x!r} {y!r} {c!r}" for r in rings for x, y in r] + [""]
        lines += [f"{len(rings[0])} 1 " + " ".join(str(i) for i in range(len(rings[0]))),
                  f"{len(rings[1])}h 1 " + " ".join(str(len(rings[0]) + i) for i in range(len(rings[1]))), ""]
        pose = np.array([[0.0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, c], [0, 0, 0, 1]])
        plane = lambda r: np.c_[r[:, 1], -r[:, 0]]  # (y, -x): the plane's coordinates
        given.append({"pose": pose, "contours": [plane(rings[0])], "holes": [plane(rings[1])]})
    (tmp_path / "torus.csl").write_text("CSLC\n" + f"{len(zs)} 2\n\n" + "\n".join(lines) + "\n")
    for method in ("nearest_plane", "section_voronoi"):
        (tmp_path / "config.yaml").write_text(
            f"input: {{csl: torus.csl}}\nreconstruction: {{voxel_size_mm: 0.4, method: {method}}}\n")
        by_file = xsect.run(tmp_path / "config.yaml")
        in_memory = xsect.reconstruct(given, method=method, reconstruction__voxel_size_mm=0.4)
        assert by_file.betti == (1, 1, 0)
        np.testing.assert_array_equal(in_memory.vertices, by_file.vertices)
        np.testing.assert_array_equal(in_memory.faces, by_file.faces)
        np.testing.assert_array_equal(in_memory.labels, by_file.labels)


def test_reconstruct_from_masks_gives_the_torus():
    # Masks of the torus on planes z = c: 0.2 mm pixels over [-20, 20]^2.
    px = 0.2
    n = int(40 / px) + 1
    x = -20 + px * np.arange(n)
    X, Y = np.meshgrid(x, x)  # rows j (y), columns i (x)
    planes = []
    for c in np.linspace(-3.8, 3.8, 20):
        mask = (np.hypot(X, Y) - 12) ** 2 + c * c < 16
        pose = np.array([[px, 0, 0, -20], [0, px, 0, -20], [0, 0, 1, c], [0, 0, 0, 1]])
        planes.append({"pose": pose, "mask": mask})
    r = xsect.reconstruct(planes, reconstruction__voxel_size_mm=0.4)
    assert r.betti == (1, 1, 0)
    assert mesh_volume(r.vertices, r.faces) == pytest.approx(2 * math.pi ** 2 * 12 * 16, rel=0.05)
    with pytest.raises(xsect.InputError) as e:
        xsect.reconstruct([planes[0], torus_sections(1)[0]])
    assert "not both" in str(e.value)


def test_two_threads_reconstructing_at_once_give_what_one_gives():
    import threading

    sections = torus_sections(16)
    alone = xsect.reconstruct(sections, method="section_voronoi", reconstruction__voxel_size_mm=0.4)
    results = [None, None]

    def work(k):
        results[k] = xsect.reconstruct(sections, method="section_voronoi", reconstruction__voxel_size_mm=0.4)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for r in results:
        np.testing.assert_array_equal(r.vertices, alone.vertices)
        np.testing.assert_array_equal(r.faces, alone.faces)
        np.testing.assert_array_equal(r.labels, alone.labels)


def test_slice_cuts_the_reconstructed_torus_in_its_annulus():
    r = xsect.reconstruct(torus_sections(), reconstruction__voxel_size_mm=0.4)
    sections = xsect.slice(r.vertices, r.faces, [np.eye(4)])  # the plane z = 0, between two inputs
    assert len(sections) == 1 and len(sections[0]) == 1  # one annulus ...
    outer, holes = sections[0][0]
    assert len(holes) == 1  # ... with one hole
    area = lambda p: 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], 1)) - np.dot(p[:, 1], np.roll(p[:, 0], 1)))
    assert area(outer) - area(holes[0]) == pytest.approx(math.pi * (16 ** 2 - 8 ** 2), rel=0.03)
    assert np.linalg.norm(outer, axis=1).mean() == pytest.approx(16, abs=0.2)
    assert np.linalg.norm(holes[0], axis=1).mean() == pytest.approx(8, abs=0.2)
    # A plane that misses the mesh has no section; an open mesh is refused.
    far = np.eye(4)
    far[2, 3] = 10.0
    assert xsect.slice(r.vertices, r.faces, [far]) == [[]]
    with pytest.raises(xsect.InputError):
        xsect.slice(r.vertices, r.faces[:-1], [np.eye(4)])


def test_progress_reports_the_stages_in_order(torus):
    stages = []
    xsect.run(torus.config, progress=stages.append)
    assert stages[:3] == ["load", "segment", "conform"]
    assert stages.index("scene") < stages.index("reconstruct") < stages.index("mesh") < stages.index("confidence")


def test_the_readmes_example_runs_as_written(tmp_path):
    readme = open(os.path.join(os.path.dirname(__file__), "..", "..", "README.md"), encoding="utf-8").read()
    block = readme.split("<!-- python-example -->", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        namespace = {}
        exec(compile(block, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    r = namespace["r"]
    assert r.betti == (1, 1, 0)
    assert (tmp_path / "torus-out" / "mesh.ply").exists() and (tmp_path / "torus-out" / "report.html").exists()
