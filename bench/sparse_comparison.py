#!/usr/bin/env python3
"""Methods 1, 2 and 3 side by side on sparse configurations (issue 22's acceptance: which method
recovers the truth's topology on sparse, non-parallel planes, and how near the surface it lies).

The configurations (29 with the default seeds; 57 with --seeds 5-12):
  - the vessel tree with planes 4 trunk radii apart (configs/phantoms/vessel-tree-sparse.yaml);
  - the genus-2 solid of configs/phantoms/genus2-random.yaml cut by 20, 30 and 40 random planes;
  - the torus of configs/phantoms/torus-multiaxial.yaml cut by 6 and 9 random planes;
  - the sphere of configs/phantoms/sphere-multiaxial.yaml cut by 6 and 9 random planes;
the random families with seeds 1-4 (--seeds for others). Each is rendered (`xsect phantom`),
reconstructed with each method (`xsect run --set reconstruction.method=...`) and evaluated
against the analytic truth (`xsect eval`). A run that fails counts as wrong and prints its exit code; a failed evaluation
prints its exit code in place of the distance.

  python3 bench/sparse_comparison.py --xsect build/xsect --work /tmp/sparse [--json out.json] [--seeds 5-8]
"""
import argparse, json, os, re, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = [("method 1", "nearest_plane"), ("method 2", "section_voronoi"), ("method 3", "delaunay")]


def spec_with(base, seed=None, count=None):
    """The phantom specification `base` (configs/phantoms) with its seed and random plane count
    (its `seed:` and `pattern:` must be one line each)."""
    text = open(os.path.join(ROOT, "configs", "phantoms", base)).read()
    for key, value, wanted in (("seed", seed, f"seed: {seed}"),
                               ("pattern", count, f"pattern: {{kind: random, count: {count}}}")):
        if value is None:
            continue
        text, n = re.subn(rf"(?m)^{key}: \S.*$", wanted, text)
        if n != 1:
            sys.exit(f"{base}: expected one line `{key}: ...`, found {n}")
    return text


def configurations(seeds=(1, 2, 3, 4)):
    yield "vessel tree, planes 4 radii apart", "vessel-tree-sparse", spec_with("vessel-tree-sparse.yaml")
    for family, base, counts in (("genus-2, 20/30/40 random planes", "genus2-random.yaml", (20, 30, 40)),
                                 ("torus, 6/9 random planes", "torus-multiaxial.yaml", (6, 9)),
                                 ("sphere, 6/9 random planes", "sphere-multiaxial.yaml", (6, 9))):
        for count in counts:
            for seed in seeds:
                yield family, f"{base.split('.')[0]}-{count}-s{seed}", spec_with(base, seed, count)


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--xsect", default=os.path.join(ROOT, "build", "xsect"))
    ap.add_argument("--work", required=True, help="folder for the phantoms and runs")
    ap.add_argument("--json", help="write the rows here")
    ap.add_argument("--seeds", default="1-4", help="seeds of the random families, as FIRST-LAST (default 1-4)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows, families = [], {}
    first, _, last = a.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    for family, name, spec in configurations(seeds):
        d = os.path.join(a.work, name)
        os.makedirs(d, exist_ok=True)
        with open(os.path.join(d, "spec.yaml"), "w") as f:
            f.write(spec)
        r = run([a.xsect, "phantom", os.path.join(d, "spec.yaml"), "--out", os.path.join(d, "ph"), "--quiet"])
        if r.returncode != 0:
            sys.exit(f"{name}: xsect phantom failed: {r.stderr}")
        truth_text = open(os.path.join(d, "ph", "truth.yaml")).read()
        truth = [int(x) for x in re.search(r"(?m)^betti: \[([^\]]*)\]", truth_text).group(1).split(",")]
        row = {"family": family, "name": name, "truth": truth}
        for label, method in METHODS:
            out = os.path.join(d, method)
            r = run([a.xsect, "run", os.path.join(d, "ph", "config.yaml"), "--out", out, "--quiet",
                     "--set", f"reconstruction.method={method}"])
            if r.returncode != 0:
                row[label] = {"exit": r.returncode, "right": False}
                continue
            rep = json.load(open(os.path.join(out, "report.json")))
            e = run([a.xsect, "eval", "--mesh", os.path.join(out, "mesh.ply"), "--truth",
                     os.path.join(d, "ph", "truth.yaml"), "--json", out + "-eval.json", "--quiet"])
            ev = json.load(open(out + "-eval.json")) if e.returncode == 0 else {}
            row[label] = {"betti": rep["betti"], "right": rep["betti"] == truth,
                          "hausdorff_mm": ev.get("hausdorff_mm"), "eval_exit": e.returncode}
        rows.append(row)
        fam = families.setdefault(family, {"configs": 0, **{label: 0 for label, _ in METHODS}})
        fam["configs"] += 1
        cells = []
        for label, _ in METHODS:
            fam[label] += row[label]["right"]
            m = row[label]
            cells.append(f"exit {m['exit']}" if "exit" in m else
                         "{} {}{}".format(tuple(m["betti"]), "ok" if m["right"] else "--",
                                          f" eval exit {m['eval_exit']}" if m["hausdorff_mm"] is None
                                          else f" {m['hausdorff_mm']:.2f} mm"))
        print(f"{name:28s} truth {tuple(truth)}  " + "  |  ".join(cells), flush=True)
    print()
    print("| family | configs | " + " | ".join(label for label, _ in METHODS) + " |")
    print("|---|---|" + "---|" * len(METHODS))
    total = {"configs": 0, **{label: 0 for label, _ in METHODS}}
    for family, fam in families.items():
        print(f"| {family} | {fam['configs']} | " + " | ".join(str(fam[label]) for label, _ in METHODS) + " |")
        for k in total:
            total[k] += fam[k]
    print(f"| **all (truth's topology)** | {total['configs']} | " +
          " | ".join(f"**{total[label]}**" for label, _ in METHODS) + " |")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"rows": rows, "families": families, "total": total}, f, indent=1)


if __name__ == "__main__":
    main()
