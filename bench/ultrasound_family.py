#!/usr/bin/env python3
"""segmentation.preset: ultrasound on a family of B-mode phantoms (issue 49, item 3): how often the
solid has the truth's Betti numbers, and how near the surface it lies.

The family (3 configurations per seed):
  - a torus with an 8 mm tube (major radius 12, minor 4) at 0.2 mm pixels;
  - a thin torus with a 5 mm tube (major 9, minor 2.5) at 0.15 mm pixels;
  - a 7 x 5 x 4 mm cyst (an ellipsoid) at 0.2 mm pixels;
each swept by 60 freehand frames of 320 x 240 px through a probe's sector (3 degrees of tilt),
rendered as B-mode frames (`degradations: {ultrasound: {}}`: Rayleigh speckle of 0.3 mm grain, a
lumen at a quarter of the tissue's echo, two reflectors per frame with their shadows), written as a
PLUS recording and reconstructed from it with the configuration the phantom writes (`preset:
ultrasound`, method 1) at the voxel size given (`--voxel`, default 0.4 mm; `auto` for the
automatic one). Each run is evaluated against the analytic truth (`xsect eval`). With `--clean`
the same sweeps are rendered without the B-mode look and segmented by the default threshold: the
distance the sweep itself allows.

  python3 bench/ultrasound_family.py --xsect build/xsect --work /tmp/us [--seeds 1-12] [--voxel auto] [--clean]
      [--look "{reflectors: 0}"] [--segmentation "{open_radius_mm: 1}"] [--smoothing "{method: shepard}"]
"""
import argparse, json, os, shutil, subprocess, sys

SHAPES = [
    ("torus", "{kind: torus, params: {major_radius: 12, minor_radius: 4}, rotation_deg: [70, 0, 0]}", 0.2),
    ("thin torus", "{kind: torus, params: {major_radius: 9, minor_radius: 2.5}, rotation_deg: [60, 20, 0]}", 0.15),
    ("cyst", "{kind: ellipsoid, params: {a: 7, b: 5, c: 4}, rotation_deg: [20, 30, 0]}", 0.2),
]


def spec(shape, pixel, seed, voxel, look, segmentation, smoothing=None, clean=False):
    seg = f", segmentation: {segmentation}" if segmentation else ""
    seg += f", smoothing: {smoothing}" if smoothing else ""
    return (f"seed: {seed}\nshape: {shape}\n"
            "pattern: {kind: freehand, count: 60, direction: [0, 0, 1], tilt_deg: 3, sector: true}\n"
            f"image: {{pixel_mm: {pixel}, width: 320, height: 240}}\n"
            + ("degradations: {}\n" if clean else f"degradations: {{ultrasound: {look}}}\n") +
            f"config: {{reconstruction: {{voxel_size_mm: {voxel}}}{seg}}}\nplus: true\n")


def seeds_of(text):
    first, _, last = text.partition("-")
    return range(int(first), int(last or first) + 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--work", required=True, help="scratch folder (its contents are replaced)")
    ap.add_argument("--seeds", default="1-3")
    ap.add_argument("--voxel", default="0.4")
    ap.add_argument("--look", default="{}", help="the phantom's degradations.ultrasound (YAML flow)")
    ap.add_argument("--segmentation", help="segmentation keys added to the preset (YAML flow)")
    ap.add_argument("--smoothing", help="the configuration's smoothing (YAML flow)")
    ap.add_argument("--clean", action="store_true",
                    help="the same sweeps without the B-mode look (threshold segmentation): what the sweep itself allows")
    ap.add_argument("--json", help="write the rows here")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows, right = [], 0
    print(f"{'shape':12} {'seed':>4}  {'betti':12} {'truth':12} {'Hausdorff mm':>12} {'Dice':>6} {'threshold':>9}")
    for seed in seeds_of(a.seeds):
        for name, shape, pixel in SHAPES:
            tag = f"{name.replace(' ', '-')}-{seed}"
            folder = os.path.join(a.work, tag)
            shutil.rmtree(folder, ignore_errors=True)  # the phantom's folder is rewritten whole
            with open(folder + ".yaml", "w") as f:
                f.write(spec(shape, pixel, seed, a.voxel, a.look, a.segmentation, a.smoothing, a.clean))
            run = lambda *args: subprocess.run([a.xsect, *args, "--quiet"], capture_output=True, text=True)
            row = {"shape": name, "seed": seed}
            p = run("phantom", folder + ".yaml", "--out", folder)
            r = run("run", os.path.join(folder, "config_plus.yaml"), "--out", os.path.join(folder, "out")) \
                if p.returncode == 0 else p
            if r.returncode != 0:
                row["exit"] = r.returncode
                print(f"{name:12} {seed:>4}  exit {r.returncode}: {r.stderr.strip().splitlines()[-1:]}")
                rows.append(row)
                continue
            out = os.path.join(folder, "out")
            e = run("eval", "--mesh", os.path.join(out, "mesh.ply"), "--truth", os.path.join(folder, "truth.yaml"),
                    "--json", os.path.join(folder, "eval.json"))
            report = json.load(open(os.path.join(out, "report.json")))
            ev = json.load(open(os.path.join(folder, "eval.json"))) if e.returncode == 0 else {}
            row.update(betti=report["betti"], truth=ev.get("truth_betti"), hausdorff_mm=ev.get("hausdorff_mm"),
                       dice=ev.get("dice"), threshold=report["segmentation"]["threshold_used"])
            right += row["betti"] == row["truth"]
            rows.append(row)
            h = f"{row['hausdorff_mm']:.2f}" if row["hausdorff_mm"] is not None else "-"
            d = f"{row['dice']:.3f}" if row["dice"] is not None else "-"
            print(f"{name:12} {seed:>4}  {str(row['betti']):12} {str(row['truth']):12} {h:>12} {d:>6} {row['threshold']:>9}")
    print(f"truth's Betti numbers on {right} of {len(rows)}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=2)


if __name__ == "__main__":
    sys.exit(main())
