#!/usr/bin/env python3
"""topology.confidence (issue 52) against the truth: how often each level's results have the truth's
Betti numbers.

The configurations: bench/topology_family.py's sparse families (the vessel tree, the genus-2 solid
cut by 20/30/40 random planes, the torus and the sphere by 6 and 9, the cup by 5 mixed planes;
seeds FIRST-LAST), and the dense multiaxial phantoms of configs/phantoms/ (their own seed), each
reconstructed with methods 1, 2 and 3 in the default configuration (`reconstruction.topology:
free`). Prints each run, then the confusion table: per level, the results right and wrong.

  python3 bench/confidence_family.py --xsect build/xsect --work /tmp/conf [--seeds 1-8] [--methods nearest_plane,section_voronoi] [--json out.json]
"""
import argparse, json, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sparse_comparison import configurations  # noqa: E402
from topology_family import cup_configurations, rendered, run, ROOT  # noqa: E402

DENSE = ["sphere-multiaxial.yaml", "torus-multiaxial.yaml", "hollow-sphere-multiaxial.yaml", "split-torus-multiaxial.yaml",
         "two-spheres-parallel.yaml", "fig-1-11-notched.yaml", "fig-1-11-twisted.yaml", "genus2-random-200.yaml",
         "vessel-tree-freehand.yaml", "ellipsoid-fan.yaml"]


def dense_configurations():
    for name in DENSE:
        p = os.path.join(ROOT, "configs", "phantoms", name)
        if os.path.exists(p):
            yield "dense multiaxial", name[:-5], open(p).read()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--seeds", default="1-8")
    ap.add_argument("--methods", default="nearest_plane,section_voronoi,delaunay")
    ap.add_argument("--only", default="")
    ap.add_argument("--json")
    a = ap.parse_args()
    first, _, last = a.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    rows = []
    confusion = {}
    configs = list(configurations(seeds)) + list(cup_configurations(seeds)) + list(dense_configurations())
    for family, name, spec in configs:
        if a.only not in name:
            continue
        d, truth = rendered(a.xsect, a.work, name, spec)
        for method in a.methods.split(","):
            out = os.path.join(d, method)
            r = run([a.xsect, "run", os.path.join(d, "ph", "config.yaml"), "--out", out, "--quiet",
                     "--set", f"reconstruction.method={method}"])
            if r.returncode != 0:
                print(f"{name:28s} {method:15s} exit {r.returncode}: {r.stderr.strip().splitlines()[-1:]}")
                continue
            rep = json.load(open(os.path.join(out, "report.json")))
            c = rep["topology"]["confidence"]
            right = rep["betti"] == truth
            rows.append({"family": family, "name": name, "method": method, "truth": truth, "betti": rep["betti"],
                         "right": right, "level": c["level"], "text": c["text"],
                         "verdict": rep["sampling"]["verdict"],
                         "confidence_s": rep["timings_s"].get("confidence"), "total_s": rep["timings_s"].get("total")})
            t = confusion.setdefault(c["level"], [0, 0])
            t[0 if right else 1] += 1
            print(f"{name:28s} {method:15s} truth {tuple(truth)} betti {tuple(rep['betti'])} {'ok' if right else '--'}"
                  f"  {c['text']}", flush=True)
    print()
    print("| level | right | wrong | share right |")
    print("|---|---|---|---|")
    for level in ("high", "medium", "low"):
        r, w = confusion.get(level, [0, 0])
        print(f"| {level} | {r} | {w} | {r / (r + w):.0%} |" if r + w else f"| {level} | 0 | 0 | - |")
    total_right = sum(v[0] for v in confusion.values())
    if total_right:
        print(f"right results rated high: {confusion.get('high', [0, 0])[0]} of {total_right}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
