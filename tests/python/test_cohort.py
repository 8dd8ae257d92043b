"""The cohort workflow (workflows/cohort/Snakefile, issue 55; docs/cohorts.md) end to end with
Snakemake: three phantoms and two broken subjects (an unknown key, a missing config), two subjects
at a time. Every good subject's row has its run's Betti numbers (the phantoms' truths), the broken
ones are reported with xsect's message and stop nothing, and a second invocation does nothing."""

import csv
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
XSECT_BIN = os.environ.get("XSECT_BIN", "xsect")
SNAKEFILE = os.path.join(ROOT, "workflows", "cohort", "Snakefile")

SPECS = {  # small phantoms with known Betti numbers
    "sphere": ("shape: {kind: sphere, params: {radius: 6}}\npattern: {kind: multiaxial, count: 5}\n"
               "image: {pixel_mm: 0.4}\nconfig: {reconstruction: {voxel_size_mm: 0.5}}\n", (1, 0, 0)),
    "torus": ("shape: {kind: torus, params: {major_radius: 10, minor_radius: 3.5}, rotation_deg: [20, 10, 0]}\n"
              "pattern: {kind: multiaxial, count: 8}\nimage: {pixel_mm: 0.4}\n"
              "config: {reconstruction: {voxel_size_mm: 0.5}}\n", (1, 1, 0)),
    "two-spheres": ("shape: {kind: two_spheres, params: {radius: 4, separation: 12}}\n"
                    "pattern: {kind: multiaxial, count: 6}\nimage: {pixel_mm: 0.4}\n"
                    "config: {reconstruction: {voxel_size_mm: 0.5}}\n", (2, 0, 0)),
}


@pytest.mark.skipif(shutil.which("snakemake") is None, reason="snakemake is not installed (scripts/install-deps.sh)")
def test_a_cohort_runs_reports_its_broken_subjects_and_resumes(tmp_path):
    rows = ["id,config,overrides"]
    for name, (spec, _) in SPECS.items():
        (tmp_path / f"{name}.yaml").write_text(spec)
        subprocess.run([XSECT_BIN, "phantom", str(tmp_path / f"{name}.yaml"), "--out", str(tmp_path / "ph" / name),
                        "--quiet"], check=True, stdout=subprocess.DEVNULL)
        rows.append(f"{name},ph/{name}/config.yaml,")
    (tmp_path / "typo.yaml").write_text(f"input: {{slices: ph/sphere/slices.yaml}}\nreconstruction: {{voxle_size_mm: 1}}\n")
    rows.append("typo,typo.yaml,")
    rows.append("missing,nowhere/config.yaml,")
    rows[1] += "reconstruction.method=section_voronoi"  # the sphere by method 2
    (tmp_path / "subjects.csv").write_text("\n".join(rows) + "\n")
    command = ["snakemake", "-s", SNAKEFILE, "--cores", "2", "--directory", str(tmp_path / "work"),
               "--config", f"subjects={tmp_path / 'subjects.csv'}", f"out={tmp_path / 'cohort'}", f"xsect={XSECT_BIN}"]
    (tmp_path / "work").mkdir()
    first = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert first.returncode == 0, first.stdout[-3000:]
    table = {r["id"]: r for r in csv.DictReader(open(tmp_path / "cohort" / "cohort.csv"))}
    assert sorted(table) == ["missing", "sphere", "torus", "two-spheres", "typo"]
    for name, (_, betti) in SPECS.items():
        r = table[name]
        assert r["status"] == "ok", r
        assert (int(r["b0"]), int(r["b1"]), int(r["b2"])) == betti, r
        assert r["verdict"] in ("satisfied", "violated", "undetermined")
        assert float(r["volume_mm3"]) > 0 and float(r["surface_area_mm2"]) > 0
        assert os.path.isfile(tmp_path / "cohort" / r["report"])
    # The sphere (radius 6): its volume within 5% of the sphere's; its faceted mesh's area above the
    # smooth sphere's and within 20% of it.
    area = float(table["sphere"]["surface_area_mm2"])
    assert 4 * 3.14159265 * 36 < area < 1.2 * 4 * 3.14159265 * 36
    assert float(table["sphere"]["volume_mm3"]) == pytest.approx(4 / 3 * 3.14159265 * 216, rel=0.05)
    assert table["typo"]["status"] == "invalid" and table["typo"]["exit_code"] == "2"
    assert "reconstruction.voxel_size_mm" in table["typo"]["message"]  # xsect's did-you-mean
    assert table["missing"]["status"] == "invalid" and "not found" in table["missing"]["message"]
    index = (tmp_path / "cohort" / "index.html").read_text()
    assert index.count("report.html") == 3
    # Resumed: nothing to do, nothing rewritten.
    stamp = os.stat(tmp_path / "cohort" / "cohort.csv").st_mtime_ns
    second = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert second.returncode == 0, second.stdout[-3000:]
    assert "Nothing to be done" in second.stdout, second.stdout[-3000:]
    assert os.stat(tmp_path / "cohort" / "cohort.csv").st_mtime_ns == stamp
