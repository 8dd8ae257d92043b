#!/usr/bin/env python3
"""Topology control (issue 51) on sparse families: the truth's Betti numbers given as
`reconstruction.topology`, and `simplest`, against the method's own solid (`free`).

The configurations are bench/sparse_comparison.py's: the vessel tree with planes 4 trunk radii
apart, the genus-2 solid cut by 20, 30 and 40 random planes, the torus by 6 and 9, the sphere by 6
and 9, seeds FIRST-LAST; and a cup with a handle cut by 5 planes of mixed orientations
(configs/phantoms/cup-mixed.yaml), tilted by each seed. Each is rendered (`xsect phantom`), reconstructed with methods 1
and 2 under each mode, and evaluated against the analytic truth (`xsect eval`: Hausdorff distance,
and the mesh's cut by every input plane against its sections, as the IoU of the two).

  python3 bench/topology_family.py --xsect build/xsect --work /tmp/topo [--seeds 1-8] [--json out.json] [--only cup]
"""
import argparse, json, os, re, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sparse_comparison import configurations  # noqa: E402

METHODS = ["nearest_plane", "section_voronoi"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def cup_configurations(seeds):
    """The cup of configs/phantoms/cup-mixed.yaml, its tilt and turn drawn from each seed."""
    base = open(os.path.join(ROOT, "configs", "phantoms", "cup-mixed.yaml")).read()
    for seed in seeds:
        rotation = [(seed * 17) % 31 - 15, (seed * 29) % 31 - 15, (seed * 73) % 360]
        text = re.sub(r"(?m)^seed: .*$", f"seed: {seed}", base)
        text = re.sub(r"(?m)^  rotation_deg: .*$", f"  rotation_deg: {rotation}", text)
        yield "cup with a handle, 5 planes of mixed orientations", f"cup-mixed-s{seed}", text


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def rendered(xsect, work, name, spec):
    """The phantom `spec` rendered in WORK/NAME/ph (once: kept for reruns); (its folder, its truth's
    Betti numbers). Exits if xsect phantom fails."""
    d = os.path.join(work, name)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "spec.yaml"), "w") as f:
        f.write(spec)
    if not os.path.exists(os.path.join(d, "ph", "truth.yaml")):
        r = run([xsect, "phantom", os.path.join(d, "spec.yaml"), "--out", os.path.join(d, "ph"), "--quiet"])
        if r.returncode != 0:
            sys.exit(f"{name}: xsect phantom failed: {r.stderr}")
    truth_text = open(os.path.join(d, "ph", "truth.yaml")).read()
    return d, [int(x) for x in re.search(r"(?m)^betti: \[([^\]]*)\]", truth_text).group(1).split(",")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--xsect", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--seeds", default="1-8")
    ap.add_argument("--json")
    ap.add_argument("--only", default="", help="only the configurations whose name holds this (e.g. cup)")
    a = ap.parse_args()
    first, _, last = a.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    os.makedirs(a.work, exist_ok=True)
    rows, tally = [], {}
    for family, name, spec in list(configurations(seeds)) + list(cup_configurations(seeds)):
        if a.only not in name:
            continue
        d, truth = rendered(a.xsect, a.work, name, spec)
        for method in METHODS:
            row = {"family": family, "name": name, "method": method, "truth": truth}
            for mode, value in (("free", "free"), ("target", "[{},{},{}]".format(*truth)), ("simplest", "simplest")):
                out = os.path.join(d, f"{method}-{mode}")
                r = run([a.xsect, "run", os.path.join(d, "ph", "config.yaml"), "--out", out, "--quiet",
                         "--set", f"reconstruction.method={method}", "--set", f"reconstruction.topology={value}"])
                if r.returncode != 0:
                    row[mode] = {"exit": r.returncode, "right": False, "error": r.stderr.strip().splitlines()[-1:]}
                    continue
                rep = json.load(open(os.path.join(out, "report.json")))
                if mode == "simplest" and truth != [1, 0, 0]:  # only where the truth is the simplest shape
                    row[mode] = {"betti": rep["betti"], "right": rep["betti"] == truth, "hausdorff_mm": None,
                                 "conformity_iou_min": None, "seconds": rep["timings_s"]["total"]}
                    continue
                e = run([a.xsect, "eval", "--mesh", os.path.join(out, "mesh.ply"), "--truth",
                         os.path.join(d, "ph", "truth.yaml"), "--slices", os.path.join(d, "ph", "slices.yaml"),
                         "--json", out + "-eval.json", "--quiet"])
                ev = json.load(open(out + "-eval.json")) if e.returncode == 0 else {}
                row[mode] = {"betti": rep["betti"], "right": rep["betti"] == truth,
                             "hausdorff_mm": ev.get("hausdorff_mm"),
                             "conformity_iou_min": ev.get("conformity_iou_min"),
                             "changes": len(rep.get("topology", {}).get("changes", [])),
                             "seconds": rep["timings_s"]["total"]}
            rows.append(row)
            t = tally.setdefault((family, method), {"configs": 0, "free": 0, "target": 0, "simplest": 0})
            t["configs"] += 1
            for mode in ("free", "target", "simplest"):
                t[mode] += row[mode]["right"]
            cells = []
            for mode in ("free", "target", "simplest"):
                m = row[mode]
                cells.append(f"{mode} exit {m['exit']}" if "exit" in m else
                             "{} {}{} {} {}".format(mode, tuple(m["betti"]), "ok" if m["right"] else "--",
                                                 "" if m["hausdorff_mm"] is None else f" {m['hausdorff_mm']:.2f}mm",
                                                 "" if m["conformity_iou_min"] is None else f"iou {m['conformity_iou_min']:.3f}"))
            print(f"{name:26s} {method:15s} truth {tuple(truth)}  " + " | ".join(cells), flush=True)
    print()
    print("| family | method | configs | free | target | simplest |")
    print("|---|---|---|---|---|---|")
    for (family, method), t in tally.items():
        print(f"| {family} | {method} | {t['configs']} | {t['free']} | {t['target']} | {t['simplest']} |")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
