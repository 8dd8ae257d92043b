#!/usr/bin/env python3
"""Several materials on a family of two-label phantoms (issue 49, item 1): how often the union and
each material have the truth's Betti numbers, per method.

The family (6 shapes per seed, each turned by a rotation drawn from the seed):
  - a torus split through its axis, off centre (two C-shaped halves, each (1, 0, 0));
  - a torus split along its middle plane (two thin rings, each (1, 1, 0));
  - a genus-2 solid split between its holes, obliquely (each half (1, 1, 0));
  - a hollow sphere split off centre (two bowls, each (1, 0, 0));
  - a sphere split off centre (each (1, 0, 0));
  - two spheres, one label each;
each cut by `--pattern` (default 12 multiaxial planes) into label images (0.25 mm pixels) and
reconstructed by each method at `--voxel` mm (default 0.35) with `--smoothing` (default none).
The truth's per-material Betti numbers are the phantom's (truth.yaml `labels`). A material's
solid has a crease where the split meets the surface (reach 0), so the thesis' sampling
conditions never hold for it: these are rates, not guarantees.

  python3 bench/materials_family.py --xsect build/xsect --work /tmp/mat [--seeds 1-3]
      [--pattern "{kind: random, count: 12}"] [--voxel 0.35] [--smoothing shepard] [--json F]
"""
import argparse, json, os, random, shutil, subprocess, sys

import yaml

from ultrasound_family import seeds_of

SHAPES = [
    ("torus-c", "{kind: torus, params: {major_radius: 7, minor_radius: 2.5}, rotation_deg: %s, "
                "label_split: {normal: [1, 0.4, 0], point: [2, 0, 0]}}"),
    ("torus-rings", "{kind: torus, params: {major_radius: 7, minor_radius: 2.5}, rotation_deg: %s, "
                    "label_split: {normal: [0, 0, 1]}}"),
    ("genus2", "{kind: genus2, params: {disk_radius: 10, hole_radius: 2.2, hole_offset: 4.5, offset_radius: 1.4}, "
               "rotation_deg: %s, label_split: {normal: [0.3, 1, 0.2]}}"),
    ("hollow", "{kind: hollow_sphere, params: {outer_radius: 7, inner_radius: 4}, rotation_deg: %s, "
               "label_split: {normal: [0.2, 0.1, 1], point: [0, 0, 1.5]}}"),
    ("sphere", "{kind: sphere, params: {radius: 6}, rotation_deg: %s, "
               "label_split: {normal: [0.5, 1, 0.3], point: [1, 1, 0]}}"),
    ("two-spheres", "{kind: two_spheres, params: {radius: 3.5, separation: 9}, rotation_deg: %s, "
                    "label_split: {normal: [1, 0, 0]}}"),
]
METHODS = ["nearest_plane", "section_voronoi", "delaunay"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--work", required=True, help="scratch folder (its phantoms' folders are replaced)")
    ap.add_argument("--seeds", default="1-3")
    ap.add_argument("--pattern", default="{kind: multiaxial, count: 12}")
    ap.add_argument("--voxel", default="0.35")
    ap.add_argument("--smoothing", default="none")
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows = []
    tally = {m: [0, 0, 0, 0] for m in METHODS}  # runs, union right, materials right, materials
    print(f"{'shape':12} {'seed':>4} {'method':16} {'union':10} {'materials (label: betti)':34} {'truth'}")
    for seed in seeds_of(a.seeds):
        rng = random.Random(seed)
        for name, shape in SHAPES:
            rotation = "[%d, %d, %d]" % tuple(rng.randrange(0, 180) for _ in range(3))
            folder = os.path.join(a.work, f"{name}-{seed}")
            shutil.rmtree(folder, ignore_errors=True)
            with open(folder + ".yaml", "w") as f:
                f.write(f"seed: {seed}\nshape: {shape % rotation}\npattern: {a.pattern}\nimage: {{pixel_mm: 0.25}}\n"
                        f"config: {{reconstruction: {{voxel_size_mm: {a.voxel}}}}}\n")
            run = lambda *args: subprocess.run([a.xsect, *args, "--quiet"], capture_output=True, text=True)
            p = run("phantom", folder + ".yaml", "--out", folder)
            if p.returncode != 0:
                print(f"{name:12} {seed:>4} phantom exit {p.returncode}: {p.stderr.strip().splitlines()[-1:]}")
                continue
            truth = yaml.safe_load(open(os.path.join(folder, "truth.yaml")))
            truth_labels = {int(k): v["betti"] for k, v in truth["labels"].items()}
            for method in METHODS:
                out = os.path.join(folder, "out-" + method)
                r = run("run", os.path.join(folder, "config.yaml"), "--out", out, "--set",
                        "reconstruction.method=" + method, "--set", "smoothing.method=" + a.smoothing)
                row = {"shape": name, "seed": seed, "method": method, "truth": truth["betti"],
                       "truth_materials": truth_labels}
                if r.returncode != 0:
                    row["exit"] = r.returncode
                    print(f"{name:12} {seed:>4} {method:16} exit {r.returncode}: {r.stderr.strip().splitlines()[-1:]}")
                    rows.append(row)
                    continue
                rep = json.load(open(os.path.join(out, "report.json")))
                mats = {m["label"]: m["betti"] for m in rep["materials"]}
                row.update(betti=rep["betti"], materials=mats, composition=rep.get("label_composition"))
                t = tally[method]
                t[0] += 1
                t[1] += rep["betti"] == truth["betti"]
                for L, b in truth_labels.items():
                    t[3] += 1
                    t[2] += mats.get(L) == b
                rows.append(row)
                got = ", ".join(f"{L}: {b}" for L, b in sorted(mats.items()))
                want = ", ".join(f"{L}: {b}" for L, b in sorted(truth_labels.items()))
                print(f"{name:12} {seed:>4} {method:16} {str(rep['betti']):10} {got:34} {truth['betti']} {want}")
    for m, (runs, union, right, materials) in tally.items():
        print(f"{m:16} union right {union}/{runs}, materials right {right}/{materials}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    sys.exit(main())
