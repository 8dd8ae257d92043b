"""Hashes of every output of `xsect run` on every phantom of configs/phantoms/ and every scenario of
bench/bench.py, to show that a change preserves behaviour (issue 16: outputs byte-identical before
and after a restructuring).

  python3 scripts/output_hashes.py --xsect build/xsect --out after.json [--work DIR]
  python3 scripts/output_hashes.py --compare before.json after.json

Every output file is hashed as written, except that report.json and manifest.json are hashed
without what a run cannot repeat (wall times, peak memory, throughput, the thread count) and with
the work folder's path replaced by "<work>"; report.html without its block of timings and memory.
"""
import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from bench import SCENARIOS  # noqa: E402  (name -> (phantom spec, --set overrides))

# Keys whose values differ from run to run of the same inputs.
UNREPEATABLE = {"timings_s", "peak_memory_mb", "throughput", "evaluate_s", "voxels_per_s", "threads", "search_s"}


def without_unrepeatable(value):
    if isinstance(value, dict):
        return {k: without_unrepeatable(v) for k, v in value.items() if k not in UNREPEATABLE}
    if isinstance(value, list):
        return [without_unrepeatable(v) for v in value]
    return value


def file_hash(path, work):
    name = os.path.basename(path)
    if name in ("report.json", "manifest.json"):
        # Paths inside are made relative to the work folder, so that two work folders compare.
        text = json.dumps(without_unrepeatable(json.load(open(path))), sort_keys=True)
        data = text.replace(os.path.abspath(work), "<work>").encode()
    elif name == "report.html":
        # The page's block of timings and memory is dropped (its markers stay).
        text = open(path, encoding="utf-8").read()
        a, b = text.find("<!--xsect-unrepeatable-begin-->"), text.find("<!--xsect-unrepeatable-end-->")
        data = (text[:a] + text[b:] if 0 <= a < b else text).replace(os.path.abspath(work), "<work>").encode()
    else:
        data = open(path, "rb").read()
    return hashlib.sha256(data).hexdigest()


def run_case(xsect, spec, sets, folder, work):
    """Renders the phantom `spec`, runs xsect on it with `sets`; {output name: hash} or an error."""
    subprocess.run([xsect, "phantom", spec, "--out", os.path.join(folder, "phantom"), "--quiet"], check=True)
    out = os.path.join(folder, "result")
    cmd = [xsect, "run", os.path.join(folder, "phantom", "config.yaml"), "--out", out, "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        return {"exit": r.returncode, "stderr": r.stderr.strip().splitlines()[-1:]}
    return {name: file_hash(os.path.join(out, name), work) for name in sorted(os.listdir(out))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--xsect", default=os.path.join(ROOT, "build", "xsect"))
    ap.add_argument("--out", help="where to write the hashes (JSON)")
    ap.add_argument("--work", default=os.path.join(ROOT, "bench", "work", "output-hashes"))
    ap.add_argument("--compare", nargs=2, metavar=("BEFORE", "AFTER"))
    a = ap.parse_args()
    if a.compare:
        before, after = (json.load(open(p)) for p in a.compare)
        differ = 0
        for case in sorted(set(before) | set(after)):
            b, c = before.get(case), after.get(case)
            if b is None or c is None:  # a case only one side ran: listed, not compared
                print(f"{'new' if b is None else 'gone'}: {case}")
                continue
            for name in sorted(set(b or {}) | set(c or {})):
                if (b or {}).get(name) != (c or {}).get(name):
                    differ += 1
                    print(f"differs: {case} {name}")
        common = set(before) & set(after)
        total = sum(len(after[c]) for c in common)
        print(f"{len(common)} cases in both, {total} outputs, {differ} differ")
        sys.exit(1 if differ else 0)
    if not a.out:
        ap.error("--out is required unless --compare is given")
    cases = {}
    phantoms = os.path.join(ROOT, "configs", "phantoms")
    for spec in sorted(os.listdir(phantoms)):
        if spec.endswith(".yaml"):
            cases["phantom " + spec[:-5]] = (os.path.join(phantoms, spec), [])
    for name, (spec, sets) in SCENARIOS.items():
        if sets:  # a scenario without overrides is its phantom's case
            cases["bench " + name] = (os.path.join(phantoms, spec), sets)
    shutil.rmtree(a.work, ignore_errors=True)
    hashes = {}
    for k, (case, (spec, sets)) in enumerate(cases.items()):
        print(f"[{k + 1}/{len(cases)}] {case}", file=sys.stderr)
        hashes[case] = run_case(a.xsect, spec, sets, os.path.join(a.work, case.replace(" ", "-")), a.work)
    with open(a.out, "w") as f:
        json.dump(hashes, f, indent=1, sort_keys=True)
        f.write("\n")
    print(f"{len(hashes)} cases, {sum(len(v) for v in hashes.values())} outputs hashed into {a.out}")


if __name__ == "__main__":
    main()
