#!/usr/bin/env python3
"""Runs the named benchmark scenarios of xsect and prints one table.

Each scenario renders a phantom (`xsect phantom`), reconstructs it (`xsect run`, whose report.json
holds per-stage wall times and the peak memory after each stage), and evaluates the result
against the analytic truth (`xsect eval`). Every command's wall time and peak RSS is measured from
outside (os.wait4). Reconstruction timings are the median over repetitions.

Baseline: CGAL's Poisson surface reconstruction (bench/poisson_baseline.cpp, target
xsect_poisson_baseline) on the contour points of the same sections, normals in the plane and
perpendicular to the contour, evaluated the same way: one "poisson" row per scenario. Its result
depends only on the phantom and the overrides that change the sections or the sampling step
(segmentation, voxel size), so it runs once per distinct (phantom, such overrides) in one
invocation and is shared by the scenarios that have them in common. --no-poisson skips it.
"""
import argparse, json, os, shutil, subprocess, sys, time

SCENARIOS = {
    # name: (phantom spec, extra --set overrides for the run)
    "freehand-400": ("vessel-tree-freehand.yaml", []),
    "multiaxial-3x40": ("torus-multiaxial-3x40.yaml", []),
    "random-200": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0"]),
    "random-400": ("genus2-random-400.yaml", ["reconstruction.end_margin_mm=1.0"]),
    "random-800": ("genus2-random-800.yaml", ["reconstruction.end_margin_mm=1.0"]),
    # a real sweep's size (issue 17): 2000 frames of 640x480 px, 0.1 mm voxels (71 M voxels)
    "freehand-2000": ("vessel-tree-freehand-2000.yaml", []),
    # freehand-400 without tracking error (what the pose error costs each reconstruction)
    "freehand-400-exact": ("vessel-tree-freehand-exact.yaml", []),
    # method 2 (Voronoi diagram of the sections) on the same inputs
    "freehand-400-m2": ("vessel-tree-freehand.yaml", ["reconstruction.method=section_voronoi"]),
    "multiaxial-3x40-m2": ("torus-multiaxial-3x40.yaml", ["reconstruction.method=section_voronoi"]),
    "random-200-m2": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0",
                                                 "reconstruction.method=section_voronoi"]),
    # method 3 (Delaunay triangulation of the sections, thesis ch. 3) on the same inputs
    "freehand-400-m3": ("vessel-tree-freehand.yaml", ["reconstruction.method=delaunay"]),
    "multiaxial-3x40-m3": ("torus-multiaxial-3x40.yaml", ["reconstruction.method=delaunay"]),
    "random-200-m3": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0",
                                                 "reconstruction.method=delaunay"]),
    # and on the other inputs of this table (not the conformity and pose variants below)
    "random-400-m3": ("genus2-random-400.yaml", ["reconstruction.end_margin_mm=1.0",
                                                 "reconstruction.method=delaunay"]),
    "random-800-m3": ("genus2-random-800.yaml", ["reconstruction.end_margin_mm=1.0",
                                                 "reconstruction.method=delaunay"]),
    "freehand-2000-m3": ("vessel-tree-freehand-2000.yaml", ["reconstruction.method=delaunay"]),
    "plus-400-m3": ("vessel-tree-plus-400.yaml", ["reconstruction.method=delaunay"]),
    "freehand-400-exact-m3": ("vessel-tree-freehand-exact.yaml", ["reconstruction.method=delaunay"]),
    # method 1 smoothed by the Shepard interpolant (thesis ch. 1 §1.1) on the same inputs
    "freehand-400-shepard": ("vessel-tree-freehand.yaml", ["smoothing.method=shepard",
                                                           "smoothing.exponent=1"]),
    "multiaxial-3x40-shepard": ("torus-multiaxial-3x40.yaml", ["smoothing.method=shepard",
                                                               "smoothing.exponent=1"]),
    "random-200-shepard": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0",
                                                      "smoothing.method=shepard",
                                                      "smoothing.exponent=1"]),
    "freehand-400-exact-shepard": ("vessel-tree-freehand-exact.yaml", ["smoothing.method=shepard",
                                                                       "smoothing.exponent=1"]),
    # tracking error (σ = 1 mm, 1°): the sections as segmented, then made to agree along their
    # intersection lines (issue 5); the freehand sweep with enforcement measures the pair search
    # on 400 frames
    "multiaxial-jitter": ("torus-multiaxial-jitter.yaml", []),
    "multiaxial-jitter-conform": ("torus-multiaxial-jitter.yaml", ["conformity.enforce=true",
                                                                   "conformity.max_correction_mm=100"]),
    "freehand-400-conform": ("vessel-tree-freehand.yaml", ["conformity.enforce=true"]),
    # pose correction (issue 19): the jittered torus (against multiaxial-jitter above), and two
    # crossing sweeps of 200 frames each (0.2 mm, 0.2°) whose crossings pin each other's poses
    "multiaxial-jitter-rigid": ("torus-multiaxial-jitter.yaml", ["conformity.pose_correction=rigid"]),
    "freehand-2x200": ("vessel-tree-two-sweeps.yaml", ["conformity.pose_correction=none"]),
    "freehand-2x200-rigid": ("vessel-tree-two-sweeps.yaml", []),
    # method 3 on the two crossing sweeps after pose correction, and on the tracked inputs above:
    # as segmented, with enforced conformity (possible since near-coincident section-vertices are
    # merged: before, the jittered torus failed closed) and with pose correction
    "freehand-2x200-rigid-m3": ("vessel-tree-two-sweeps.yaml", ["reconstruction.method=delaunay"]),
    "freehand-2x200-m3": ("vessel-tree-two-sweeps.yaml", ["conformity.pose_correction=none",
                                                          "reconstruction.method=delaunay"]),
    "multiaxial-jitter-m3": ("torus-multiaxial-jitter.yaml", ["reconstruction.method=delaunay"]),
    "multiaxial-jitter-conform-m3": ("torus-multiaxial-jitter.yaml", ["conformity.enforce=true",
                                                                      "conformity.max_correction_mm=100",
                                                                      "reconstruction.method=delaunay"]),
    "multiaxial-jitter-rigid-m3": ("torus-multiaxial-jitter.yaml", ["conformity.pose_correction=rigid",
                                                                    "reconstruction.method=delaunay"]),
    "freehand-400-conform-m3": ("vessel-tree-freehand.yaml", ["conformity.enforce=true",
                                                             "reconstruction.method=delaunay"]),
    # topology control (issue 51): the truth's Betti numbers given (reconstruction.topology), on
    # the dense inputs above (nothing to change: the cost of finding so) and on the 60 random
    # planes through the genus-2 solid of configs/phantoms/genus2-random.yaml
    "random-200-topo": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0",
                                                   "reconstruction.topology=[1,2,0]"]),
    "multiaxial-3x40-topo": ("torus-multiaxial-3x40.yaml", ["reconstruction.topology=[1,1,0]"]),
    "genus2-sparse": ("genus2-random.yaml", []),
    "genus2-sparse-topo": ("genus2-random.yaml", ["reconstruction.topology=[1,2,0]"]),
    # a PLUS tracked-ultrasound recording (issue 20): the freehand vessel tree as 400 frames of
    # 820x616 px (the size of PLUS's N-wire example) in one zlib-compressed .igs.mha with its device
    # set, read through input.plus_sequence (config_plus.yaml); frames/s of load + segment. Its
    # Poisson row reads the same phantom's config.yaml (slices.yaml: the same frames and poses)
    "plus-400": ("vessel-tree-plus-400.yaml", []),
    # B-mode frames with speckle and shadows, segmented by segmentation.preset: ultrasound
    "plus-ultrasound": ("torus-ultrasound-plus.yaml", []),
}
# The run configuration the phantom folder provides for a scenario (default config.yaml).
RUN_CONFIG = {"plus-400": "config_plus.yaml", "plus-400-m3": "config_plus.yaml", "plus-ultrasound": "config_plus.yaml"}
QUICK = ["freehand-400", "multiaxial-3x40", "random-200", "freehand-400-m2", "freehand-400-shepard"]
METHOD_LABELS = {"nearest_plane": "method 1", "section_voronoi": "method 2", "delaunay": "method 3"}
BASES = ["freehand-400", "multiaxial-3x40", "random-200", "freehand-400-exact"]
# Overrides that change what the Poisson baseline sees (the sections, the sampling step).
POISSON_KEYS = ("input.", "segmentation.", "reconstruction.voxel_size_mm")


def run(cmd, fatal=True):
    """Wall time (s) and peak RSS (MB) of cmd; exits on failure, or with fatal=False returns
    (None, None, message)."""
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    err = p.stderr.read().decode()  # before waiting: a full pipe would block the child
    _, status, usage = os.wait4(p.pid, 0)
    p.stderr.close()
    wall = time.monotonic() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        if fatal:
            sys.exit(f"failed: {' '.join(cmd)}\n{err}")
        return None, None, f"exit {os.waitstatus_to_exitcode(status)}: {err.strip()}"
    if fatal:
        return wall, usage.ru_maxrss / 1024.0
    return wall, usage.ru_maxrss / 1024.0, None


def poisson_baseline(a, d, sets, reps):
    """Runs the Poisson baseline on the phantom in d (with the given overrides) reps times (times:
    the median) and evaluates the last mesh (they differ by a few triangles at most: see
    poisson_baseline.cpp).
    Returns the results entry; on failure {"error": message}."""
    out = os.path.join(d, "poisson")
    os.makedirs(out, exist_ok=True)
    mesh, stats_json, ev_json = (os.path.join(out, f) for f in ("poisson.ply", "poisson.json", "eval.json"))
    cmd = [a.poisson, os.path.join(d, "phantom", "config.yaml"), "--out", mesh, "--json", stats_json]
    for s in sets:
        cmd += ["--set", s]
    walls, mems, stages = [], [], []
    for _ in range(reps):
        wall, mem, err = run(cmd, fatal=False)
        if err:
            return {"error": err, "sets": sets}
        st = json.load(open(stats_json))
        walls.append(wall)
        mems.append(mem)
        stages.append(st.get("poisson_s"))
    wall, mem = median(walls), max(mems)
    st["poisson_s"] = None if None in stages else median(stages)
    ev_wall, ev_mem, err = run([a.xsect, "eval", "--mesh", mesh,
                                "--truth", os.path.join(d, "phantom", "truth.yaml"),
                                "--slices", os.path.join(d, "phantom", "slices.yaml"),
                                "--json", ev_json, "--quiet"], fatal=False)
    ev = {} if err else json.load(open(ev_json))
    return {
        "wall_s": wall, "peak_memory_mb": mem,
        "poisson_s": st.get("poisson_s"), "sampling_s": st.get("sampling_s"),
        "points": st.get("points"), "spacing_mm": st.get("spacing_mm"),
        "sample_step_mm": st.get("sample_step_mm"),
        "vertices": st.get("vertices"), "triangles": st.get("triangles"),
        "closed": st.get("closed"), "orientation_flipped": st.get("orientation_flipped"),
        "eval": {"wall_s": ev_wall, "peak_memory_mb": ev_mem, "error": err},
        "betti": ev.get("betti"), "truth_betti": ev.get("truth_betti"),
        "watertight": ev.get("watertight"),
        "hausdorff_mm": ev.get("hausdorff_mm"), "mean_distance_mm": ev.get("mean_distance_mm"),
        "dice": ev.get("dice"), "conformity_iou_min": ev.get("conformity_iou_min"),
        "sets": sets, "repetitions": reps,
    }


def wide_min(ev, voxel):
    """Smallest conformity IoU over planes whose sections are at least 10 voxels wide
    (hydraulic diameter 4 A / P, as in the acceptance tests); None if there is none."""
    vals = [p["iou"] for p in ev.get("conformity", [])
            if p["iou"] is not None and p["section_perimeter_mm"] > 0
            and 4 * p["section_area_mm2"] / p["section_perimeter_mm"] >= 10 * voxel]
    return min(vals) if vals else None


def median(xs):
    xs = sorted(xs)
    return xs[len(xs) // 2]


def print_poisson(name, r):
    """The "poisson" row(s) of a scenario, if it has the baseline."""
    p = r.get("poisson")
    if p is None:
        return
    shared = "" if p["computed_in"] == name else f" (same as {p['computed_in']})"
    if "error" in p:
        print(f"{'':<16} {'poisson':<12} {'n/a':>8} {'n/a':>8}  failed{shared}: {p['error']}")
    else:
        f3 = lambda v: "n/a" if v is None else f"{v:.3f}"
        f4 = lambda v: "n/a" if v is None else f"{v:.4f}"
        print(f"{'':<16} {'poisson':<12} {p['wall_s']:8.3f} {p['peak_memory_mb']:8.0f}"
              f"  CGAL Poisson stage {p['poisson_s']:.3f} s on {p['points']} contour points"
              f" (step {p['sample_step_mm']} mm, spacing {p['spacing_mm']:.3f} mm){shared}")
        closed = "closed" if p["closed"] else "OPEN"
        print(f"{'':<16} {'':<12} {'':>8} {'':>8}  hausdorff {f3(p['hausdorff_mm'])} mm, "
              f"mean {f3(p['mean_distance_mm'])} mm, dice {f4(p['dice'])}, "
              f"betti {p['betti']} truth {p['truth_betti']}, {p['triangles']} triangles, {closed}"
              + (f", eval failed: {p['eval']['error']}" if p["eval"]["error"] else ""))


def add_poisson(a, name, spec, sets, d, results, cache, reps):
    """results[name]["poisson"]: the baseline for this phantom, computed once per
    (phantom spec, overrides that change the sections or the sampling step)."""
    if a.no_poisson:
        return
    psets = [s for s in sets if s.startswith(POISSON_KEYS)]
    key = (spec, tuple(sorted(psets)))
    if key not in cache:
        cache[key] = dict(poisson_baseline(a, d, psets, reps), computed_in=name)
    results[name]["poisson"] = cache[key]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--quick", action="store_true", help="the QUICK scenarios, one repetition")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--poisson", help="xsect_poisson_baseline (default: beside --xsect, if built)")
    ap.add_argument("--no-poisson", action="store_true", help="skip the CGAL Poisson baseline")
    ap.add_argument("--results", help="results file (default ROOT/bench/results.json)")
    ap.add_argument("--work", help="scratch folder, emptied first (default ROOT/bench/work)")
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    names = a.scenarios or (QUICK if a.quick else list(SCENARIOS))
    unknown = [n for n in names if n not in SCENARIOS]
    if unknown:
        sys.exit(f"unknown scenario(s): {', '.join(unknown)} (known: {', '.join(SCENARIOS)})")
    reps = 1 if a.quick else a.repeat
    if not a.no_poisson and not a.poisson:
        guess = os.path.join(os.path.dirname(os.path.abspath(a.xsect)), "xsect_poisson_baseline")
        if os.access(guess, os.X_OK):
            a.poisson = guess
        else:
            print(f"no Poisson baseline at {guess} (build target xsect_poisson_baseline, or pass "
                  f"--poisson PATH); skipping it", file=sys.stderr)
            a.no_poisson = True
    results_path = a.results or os.path.join(a.root, "bench", "results.json")
    work = a.work or os.path.join(a.root, "bench", "work")
    shutil.rmtree(work, ignore_errors=True)
    results = {}
    poisson_cache = {}  # (phantom spec, overrides that matter) -> results entry
    for name in names:
        spec, sets = SCENARIOS[name]
        d = os.path.join(work, name)
        ph_wall, ph_mem = run([a.xsect, "phantom", os.path.join(a.root, "configs", "phantoms", spec),
                               "--out", os.path.join(d, "phantom"), "--quiet"])
        reports, walls, mems, failed = [], [], [], None
        for r in range(reps):
            out = os.path.join(d, "result")
            cmd = [a.xsect, "run", os.path.join(d, "phantom", RUN_CONFIG.get(name, "config.yaml")), "--out", out,
                   "--quiet"]
            for s in sets:
                cmd += ["--set", s]
            w, m, failed = run(cmd, fatal=False)
            if failed:
                break
            walls.append(w)
            mems.append(m)
            reports.append(json.load(open(os.path.join(out, "report.json"))))
        if failed:
            # Reported, not fatal: the other scenarios (and this phantom's Poisson row) still count.
            results[name] = {"error": f"xsect run {' '.join(sets)}: {failed}",
                             "phantom": {"wall_s": ph_wall, "peak_memory_mb": ph_mem}}
            add_poisson(a, name, spec, sets, d, results, poisson_cache, reps)
            continue
        ev_json = os.path.join(d, "eval.json")
        ev_wall, ev_mem = run([a.xsect, "eval", "--mesh", os.path.join(d, "result", "mesh.ply"),
                               "--truth", os.path.join(d, "phantom", "truth.yaml"),
                               "--slices", os.path.join(d, "phantom", "slices.yaml"),
                               "--json", ev_json, "--quiet"])
        ev = json.load(open(ev_json))
        rep = reports[-1]
        stages = {}
        for stage in rep["timings_s"]:
            if stage == "total":
                continue
            stages[stage] = {"wall_s": median([r["timings_s"][stage] for r in reports]),
                             "peak_memory_mb": rep["peak_memory_mb"].get(stage)}
        vps = median([r["throughput"]["reconstruct_voxels_per_s"] for r in reports])
        # input throughput: frames read and segmented per second (load + segment stages)
        fps = median([r["counts"]["slices"] / (r["timings_s"]["load"] + r["timings_s"]["segment"])
                      for r in reports if r["timings_s"].get("load", 0) + r["timings_s"].get("segment", 0) > 0] or [0])
        smooth_eval = [r.get("smoothing", {}).get("evaluate_s") if isinstance(r.get("smoothing"), dict)
                       else None for r in reports]
        results[name] = {
            "phantom": {"wall_s": ph_wall, "peak_memory_mb": ph_mem},
            "run": {"wall_s": median(walls), "peak_memory_mb": max(mems)},
            "eval": {"wall_s": ev_wall, "peak_memory_mb": ev_mem},
            "stages": stages,
            "sampling": ({"diagnosis_s": median([r["sampling"]["timings_s"]["diagnosis"] for r in reports]),
                          "advice_s": median([r["sampling"]["timings_s"]["advice"] for r in reports]),
                          "advice_slices": rep["sampling"]["advice"]["slices"],
                          "verdict": rep["sampling"]["verdict"]} if "sampling" in rep else None),
            "voxels": rep["counts"]["voxels"],
            # report.html (issue 21): its size, and the run's time after its stages (writing every output)
            "report_html_mb": os.path.getsize(os.path.join(d, "result", "report.html")) / 1e6
            if os.path.exists(os.path.join(d, "result", "report.html")) else None,
            "write_s": median([w - r["timings_s"]["total"] for w, r in zip(walls, reports)]),
            "planes": rep["counts"]["slices"],
            "method": rep["reconstruction"]["method"],
            "voxels_per_s": vps,
            "load_segment_frames_per_s": fps,
            "evaluate_s": median([r["throughput"]["evaluate_s"] for r in reports]),
            "cells": rep["counts"]["cells"],
            "betti": rep["betti"], "truth_betti": ev.get("truth_betti"),
            "hausdorff_mm": ev.get("hausdorff_mm"), "mean_distance_mm": ev.get("mean_distance_mm"),
            "dice": ev.get("dice"), "conformity_iou_min": ev.get("conformity_iou_min"),
            "conformity_iou_min_wide": wide_min(ev, rep["reconstruction"]["voxel_size_mm"]),
            "repetitions": reps,
            "conformity": {k: rep.get("conformity", {}).get(k) for k in
                           ("pairs", "before", "after", "pairs_enforced", "endpoint_moves",
                            "edits_added", "edits_removed", "flagged_slices")},
        }
        d3 = rep["reconstruction"].get("delaunay")
        if d3 is not None:  # method 3: its own costs and counts (reconstruct = Delaunay + voxelisation)
            results[name]["delaunay"] = {
                "delaunay_s": median([r["throughput"]["method3_delaunay_s"] for r in reports]),
                "voxelise_s": median([r["throughput"]["method3_voxelise_s"] for r in reports]),
                **{k: d3.get(k) for k in ("cells", "section_vertices", "branching_points", "conformity_points",
                                          "d3", "tetrahedra_components", "connections", "edges_g_double_prime",
                                          "voxel_betti", "mesh_betti", "singular_edges", "singular_vertices",
                                          "open_edges")}}
        if rep.get("smoothing") is not None or any(s.startswith("smoothing.") for s in sets):
            results[name]["smoothing_evaluate_s"] = (None if None in smooth_eval else median(smooth_eval))
        add_poisson(a, name, spec, sets, d, results, poisson_cache, reps)
    print(f"{'scenario':<16} {'stage':<12} {'wall s':>8} {'peak MB':>8}  throughput / accuracy")
    for name, r in results.items():
        print(f"{name:<16} {'phantom':<12} {r['phantom']['wall_s']:8.3f} {r['phantom']['peak_memory_mb']:8.0f}")
        if "error" in r:
            print(f"{'':<16} {'run':<12} {'n/a':>8} {'n/a':>8}  FAILED: {r['error']}")
            print_poisson(name, r)
            continue
        for stage, s in r["stages"].items():
            extra = ""
            if stage == "reconstruct":
                label = METHOD_LABELS.get(r["method"], r["method"])
                if r.get("delaunay"):
                    d = r["delaunay"]
                    extra = (f"  {label}: Delaunay {d['delaunay_s']:.3f} s ({d['section_vertices']} section-vertices, "
                             f"{d['d3']} tetrahedra kept in {d['cells']} cells), voxelisation {d['voxelise_s']:.3f} s "
                             f"({r['voxels'] / 1e6:.2f} Mvoxel)")
                else:
                    extra = (f"  {label}: {r['voxels_per_s'] / 1e6:.1f} Mvoxel/s "
                             f"({r['voxels'] / 1e6:.2f} Mvoxel, {r['planes']} planes)")
            if stage == "segment" and r.get("load_segment_frames_per_s"):
                extra = f"  load + segment: {r['load_segment_frames_per_s']:.0f} frames/s ({r['planes']} frames)"
            if stage == "arrange":
                extra = f"  {r['cells']} cells with sections, graphs " + {
                    "nearest_plane": "G", "section_voronoi": "G and G'",
                    "delaunay": "G, G' and G'' with the branching diagram"}.get(r["method"], "G")
            if stage == "conform":
                c = r.get("conformity") or {}
                b, af = c.get("before") or {}, c.get("after")
                extra = (f"  {c.get('pairs')} pairs of slices, median mismatch {b.get('median_mismatch_mm', 0):.2f} mm"
                         + ("" if af is None else
                            f", enforced on {c.get('pairs_enforced')}: after max {af['max_mismatch_mm']:.1e} mm"
                            f" ({c.get('endpoint_moves')} moves, {c.get('edits_added')}+{c.get('edits_removed')} edits)"))
            if stage == "sampling" and r.get("sampling"):
                sm = r["sampling"]
                rest = r["run"]["wall_s"] - s["wall_s"]
                extra = (f"  diagnosis {sm['diagnosis_s']:.3f} s ({100 * sm['diagnosis_s'] / rest:.0f}% of the rest of "
                         f"the run), advice of {sm['advice_slices']} slices {sm['advice_s']:.3f} s; verdict {sm['verdict']}")
            if stage == "smooth":
                ev = r.get("smoothing_evaluate_s")
                extra = "  Shepard interpolant evaluation " + ("n/a" if ev is None else f"{ev:.3f} s")
            print(f"{'':<16} {stage:<12} {s['wall_s']:8.3f} {s['peak_memory_mb'] or 0:8.0f}{extra}")
        print(f"{'':<16} {'run (total)':<12} {r['run']['wall_s']:8.3f} {r['run']['peak_memory_mb']:8.0f}"
              f"  betti {r['betti']} truth {r['truth_betti']}")
        if r.get("report_html_mb") is not None:
            print(f"{'':<16} {'outputs':<12} {r['write_s']:8.3f} {'':>8}  after the stages (process start and exit "
                  f"too); report.html {r['report_html_mb']:.2f} MB")
        cim, ciw = r['conformity_iou_min'], r['conformity_iou_min_wide']
        fmt = lambda v: "n/a" if v is None else f"{v:.4f}"
        print(f"{'':<16} {'eval':<12} {r['eval']['wall_s']:8.3f} {r['eval']['peak_memory_mb']:8.0f}"
              f"  hausdorff {r['hausdorff_mm']:.3f} mm, mean {r['mean_distance_mm']:.3f} mm, "
              f"dice {r['dice']:.4f}, conformity IoU min {fmt(cim)} (sections >= 10 voxels wide: {fmt(ciw)})")
        print_poisson(name, r)
    ok = lambda n: n in results and "error" not in results[n]
    if ok("random-200") and ok("random-400"):
        a2, a4 = results["random-200"], results["random-400"]
        ratio = (a4["evaluate_s"] / a4["voxels"]) / (a2["evaluate_s"] / a2["voxels"])
        stage = (a4["stages"]["reconstruct"]["wall_s"] / a4["voxels"]) / (a2["stages"]["reconstruct"]["wall_s"] / a2["voxels"])
        print(f"doubling planes (random-200 -> random-400), time per voxel: reconstruct stage x{stage:.2f}, "
              f"method-1 evaluation alone x{ratio:.2f}")
        results["doubling_planes_time_ratio"] = {"reconstruct_stage": stage, "method1_evaluation": ratio}
        # The whole run and the arrange stage as the planes double (issue 17: at most x1.5 wanted).
        growth = {}
        for small, large in (("random-200", "random-400"), ("random-400", "random-800")):
            if ok(small) and ok(large):
                a, b = results[small], results[large]
                growth[f"{small}->{large}"] = {
                    "run": b["run"]["wall_s"] / a["run"]["wall_s"],
                    "arrange": b["stages"]["arrange"]["wall_s"] / a["stages"]["arrange"]["wall_s"],
                    "reconstruct": b["stages"]["reconstruct"]["wall_s"] / a["stages"]["reconstruct"]["wall_s"]}
                g = growth[f"{small}->{large}"]
                print(f"doubling planes ({small} -> {large}): whole run x{g['run']:.2f}, arrange x{g['arrange']:.2f}, "
                      f"reconstruct x{g['reconstruct']:.2f}")
        results["doubling_planes_run_ratio"] = growth
    ok = lambda n: n in results and "error" not in results[n]
    for base in BASES:
        if ok(base) and ok(base + "-m2"):
            m1, m2 = results[base]["stages"]["reconstruct"]["wall_s"], results[base + "-m2"]["stages"]["reconstruct"]["wall_s"]
            print(f"method 2 / method 1 reconstruct stage on {base}: x{m2 / m1:.2f} ({m2:.3f} s / {m1:.3f} s)")
            results.setdefault("method2_over_method1_reconstruct", {})[base] = m2 / m1
    for base in [n[:-3] for n in SCENARIOS if n.endswith("-m3")]:
        if base + "-m3" in results and not ok(base + "-m3"):
            print(f"method 3 on {base}: {results[base + '-m3']['error']}")
        if ok(base) and ok(base + "-m3"):
            b, m3 = results[base], results[base + "-m3"]
            m1 = b["stages"]["reconstruct"]["wall_s"]
            # method 3's graphs (G' and the branching diagram) are built in the arrange stage
            a1, a3 = b["stages"]["arrange"]["wall_s"], m3["stages"]["arrange"]["wall_s"]
            r3 = m3["stages"]["reconstruct"]["wall_s"]
            w1, w3 = b["run"]["wall_s"], m3["run"]["wall_s"]
            print(f"method 3 / method 1 on {base}: whole run x{w3 / w1:.2f} ({w3:.3f} s / {w1:.3f} s), "
                  f"reconstruct x{r3 / m1:.2f} ({r3:.3f} s / {m1:.3f} s), "
                  f"arrange + reconstruct x{(a3 + r3) / (a1 + m1):.2f}; mean distance {m3['mean_distance_mm']:.3f} "
                  f"vs {b['mean_distance_mm']:.3f} mm, betti {m3['betti']} vs {b['betti']} (truth {b['truth_betti']})")
            results.setdefault("method3_over_method1_reconstruct", {})[base] = r3 / m1
            results.setdefault("method3_over_method1_run", {})[base] = w3 / w1
    for base in BASES:
        sh = results.get(base + "-shepard")
        if sh is None:
            continue
        if "error" in sh:
            print(f"shepard on {base}: n/a (run failed)")
            continue
        smooth = sh["stages"].get("smooth", {}).get("wall_s")
        m1 = (results[base] if ok(base) else sh)["stages"]["reconstruct"]["wall_s"]
        ev = sh.get("smoothing_evaluate_s")
        evs = "n/a" if ev is None else f"{ev:.3f} s"
        if smooth is None:
            print(f"shepard / method 1 reconstruct on {base}: n/a (no smooth stage in report.json)")
        else:
            print(f"shepard / method 1 reconstruct on {base}: x{smooth / m1:.2f} "
                  f"(smooth stage {smooth:.3f} s, interpolant evaluation {evs} / {m1:.3f} s)")
            results.setdefault("shepard_over_method1_reconstruct", {})[base] = smooth / m1
        p = sh.get("poisson")
        if p is None or "error" in p:
            if p is not None:
                print(f"shepard vs poisson on {base}: n/a (Poisson failed)")
            continue
        sd, pd = sh.get("mean_distance_mm"), p.get("mean_distance_mm")
        ratio = sh["run"]["wall_s"] / p["wall_s"]
        stage = None if smooth is None or not p["poisson_s"] else smooth / p["poisson_s"]
        f3 = lambda v: "n/a" if v is None else f"{v:.3f}"
        print(f"shepard vs poisson on {base}: time x{ratio:.2f} (xsect run {sh['run']['wall_s']:.3f} s "
              f"vs Poisson process {p['wall_s']:.3f} s; smooth stage / Poisson stage "
              f"{'n/a' if stage is None else f'x{stage:.2f}'}), mean distance shepard {f3(sd)} mm "
              f"vs poisson {f3(pd)} mm, hausdorff {f3(sh.get('hausdorff_mm'))} vs {f3(p.get('hausdorff_mm'))} mm")
        results.setdefault("shepard_vs_poisson", {})[base] = {
            "run_over_poisson_wall": ratio, "smooth_over_poisson_stage": stage,
            "shepard_mean_distance_mm": sd, "poisson_mean_distance_mm": pd,
            "shepard_faster": ratio < 1,
            "shepard_closer": None if sd is None or pd is None else sd < pd}
    os.makedirs(os.path.dirname(os.path.abspath(results_path)), exist_ok=True)
    with open(results_path, "w") as f:
        json.dump(results, f, indent=2)
    print(f"written {results_path}")
    failures = [n for n, r in results.items() if isinstance(r, dict) and "error" in r]
    if failures:
        sys.exit(f"failed scenarios: {', '.join(failures)}")


if __name__ == "__main__":
    main()
