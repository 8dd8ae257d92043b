#!/usr/bin/env python3
"""Runs the named benchmark scenarios of xsect and prints one table.

Each scenario renders a phantom (`xsect phantom`), reconstructs it (`xsect run`, whose report.json
holds per-stage wall times and the peak memory after each stage), and evaluates the result
against the analytic truth (`xsect eval`). Every command's wall time and peak RSS is measured from
outside (os.wait4). Reconstruction timings are the median over repetitions.
"""
import argparse, json, os, shutil, subprocess, sys, time

SCENARIOS = {
    # name: (phantom spec, extra --set overrides for the run)
    "freehand-400": ("vessel-tree-freehand.yaml", []),
    "multiaxial-3x40": ("torus-multiaxial-3x40.yaml", []),
    "random-200": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0"]),
    "random-400": ("genus2-random-400.yaml", ["reconstruction.end_margin_mm=1.0"]),
    # method 2 (Voronoi diagram of the sections) on the same inputs
    "freehand-400-m2": ("vessel-tree-freehand.yaml", ["reconstruction.method=section_voronoi"]),
    "multiaxial-3x40-m2": ("torus-multiaxial-3x40.yaml", ["reconstruction.method=section_voronoi"]),
    "random-200-m2": ("genus2-random-200.yaml", ["reconstruction.end_margin_mm=1.0",
                                                 "reconstruction.method=section_voronoi"]),
}
QUICK = ["freehand-400", "multiaxial-3x40", "random-200", "freehand-400-m2"]


def run(cmd):
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    err = p.stderr.read().decode()
    p.stderr.close()
    wall = time.monotonic() - t0
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{err}")
    return wall, usage.ru_maxrss / 1024.0


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--quick", action="store_true", help="three scenarios, one repetition")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("scenarios", nargs="*")
    a = ap.parse_args()
    names = a.scenarios or (QUICK if a.quick else list(SCENARIOS))
    reps = 1 if a.quick else a.repeat
    work = os.path.join(a.root, "bench", "work")
    shutil.rmtree(work, ignore_errors=True)
    results = {}
    for name in names:
        spec, sets = SCENARIOS[name]
        d = os.path.join(work, name)
        ph_wall, ph_mem = run([a.xsect, "phantom", os.path.join(a.root, "configs", "phantoms", spec),
                               "--out", os.path.join(d, "phantom"), "--quiet"])
        reports, walls, mems = [], [], []
        for r in range(reps):
            out = os.path.join(d, "result")
            cmd = [a.xsect, "run", os.path.join(d, "phantom", "config.yaml"), "--out", out, "--quiet"]
            for s in sets:
                cmd += ["--set", s]
            w, m = run(cmd)
            walls.append(w)
            mems.append(m)
            reports.append(json.load(open(os.path.join(out, "report.json"))))
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
        results[name] = {
            "phantom": {"wall_s": ph_wall, "peak_memory_mb": ph_mem},
            "run": {"wall_s": median(walls), "peak_memory_mb": max(mems)},
            "eval": {"wall_s": ev_wall, "peak_memory_mb": ev_mem},
            "stages": stages,
            "voxels": rep["counts"]["voxels"],
            "planes": rep["counts"]["slices"],
            "method": rep["reconstruction"]["method"],
            "voxels_per_s": vps,
            "evaluate_s": median([r["throughput"]["evaluate_s"] for r in reports]),
            "cells": rep["counts"]["cells"],
            "betti": rep["betti"], "truth_betti": ev.get("truth_betti"),
            "hausdorff_mm": ev.get("hausdorff_mm"), "mean_distance_mm": ev.get("mean_distance_mm"),
            "dice": ev.get("dice"), "conformity_iou_min": ev.get("conformity_iou_min"),
            "conformity_iou_min_wide": wide_min(ev, rep["reconstruction"]["voxel_size_mm"]),
            "repetitions": reps,
        }
    print(f"{'scenario':<16} {'stage':<12} {'wall s':>8} {'peak MB':>8}  throughput / accuracy")
    for name, r in results.items():
        print(f"{name:<16} {'phantom':<12} {r['phantom']['wall_s']:8.3f} {r['phantom']['peak_memory_mb']:8.0f}")
        for stage, s in r["stages"].items():
            extra = ""
            if stage == "reconstruct":
                label = "method 1" if r["method"] == "nearest_plane" else "method 2"
                extra = (f"  {label}: {r['voxels_per_s'] / 1e6:.1f} Mvoxel/s "
                         f"({r['voxels'] / 1e6:.2f} Mvoxel, {r['planes']} planes)")
            if stage == "arrange":
                extra = f"  {r['cells']} cells with sections, graphs G" + ("" if r["method"] == "nearest_plane" else " and G'")
            print(f"{'':<16} {stage:<12} {s['wall_s']:8.3f} {s['peak_memory_mb'] or 0:8.0f}{extra}")
        print(f"{'':<16} {'run (total)':<12} {r['run']['wall_s']:8.3f} {r['run']['peak_memory_mb']:8.0f}"
              f"  betti {r['betti']} truth {r['truth_betti']}")
        cim, ciw = r['conformity_iou_min'], r['conformity_iou_min_wide']
        fmt = lambda v: "n/a" if v is None else f"{v:.4f}"
        print(f"{'':<16} {'eval':<12} {r['eval']['wall_s']:8.3f} {r['eval']['peak_memory_mb']:8.0f}"
              f"  hausdorff {r['hausdorff_mm']:.3f} mm, mean {r['mean_distance_mm']:.3f} mm, "
              f"dice {r['dice']:.4f}, conformity IoU min {fmt(cim)} (sections >= 10 voxels wide: {fmt(ciw)})")
    if "random-200" in results and "random-400" in results:
        a2, a4 = results["random-200"], results["random-400"]
        ratio = (a4["evaluate_s"] / a4["voxels"]) / (a2["evaluate_s"] / a2["voxels"])
        stage = (a4["stages"]["reconstruct"]["wall_s"] / a4["voxels"]) / (a2["stages"]["reconstruct"]["wall_s"] / a2["voxels"])
        print(f"doubling planes (random-200 -> random-400), time per voxel: reconstruct stage x{stage:.2f}, "
              f"method-1 evaluation alone x{ratio:.2f}")
        results["doubling_planes_time_ratio"] = {"reconstruct_stage": stage, "method1_evaluation": ratio}
    for base in ["freehand-400", "multiaxial-3x40", "random-200"]:
        if base in results and base + "-m2" in results:
            m1, m2 = results[base]["stages"]["reconstruct"]["wall_s"], results[base + "-m2"]["stages"]["reconstruct"]["wall_s"]
            print(f"method 2 / method 1 reconstruct stage on {base}: x{m2 / m1:.2f} ({m2:.3f} s / {m1:.3f} s)")
            results.setdefault("method2_over_method1_reconstruct", {})[base] = m2 / m1
    with open(os.path.join(a.root, "bench", "results.json"), "w") as f:
        json.dump(results, f, indent=2)
    print(f"written {os.path.join(a.root, 'bench', 'results.json')}")


if __name__ == "__main__":
    main()
