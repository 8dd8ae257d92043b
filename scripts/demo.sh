#!/usr/bin/env bash
# The demo: installs what is missing, builds the xsect tool (not the tests), renders a torus phantom
# cut by three orthogonal stacks of slices (configs/phantoms/torus-demo.yaml), reconstructs it
# (method 1, smoothed by the Shepard interpolant), measures it against the analytic torus, and ends
# with the result in plain words and where to look. Everything it writes is under out/demo.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
step() { printf '\n== %s\n' "$*"; }

step "Debian packages xsect needs (installed when missing)"
"$root/scripts/install-deps.sh"
step "Building the xsect tool (a first build takes about 6 minutes on 2 cores)"
"$root/scripts/build.sh" xsect
xsect="${XSECT_BUILD_DIR:-$root/build}/xsect"
demo="$root/out/demo"
rm -rf "$demo"  # the demo's own folder, made anew each time
mkdir -p "$demo"

step "A torus phantom: 30 slices in three orthogonal stacks, with its analytic truth"
"$xsect" phantom "$root/configs/phantoms/torus-demo.yaml" --out "$demo/torus" --quiet
echo "written: $demo/torus (images/, slices.yaml, config.yaml, truth.yaml)"
step "Reconstructing it: xsect run $demo/torus/config.yaml"
"$xsect" run "$demo/torus/config.yaml" --out "$demo/result"
step "Measuring it against the truth: xsect eval"
"$xsect" eval --mesh "$demo/result/mesh.ply" --truth "$demo/torus/truth.yaml" \
  --slices "$demo/torus/slices.yaml" --json "$demo/eval.json" --quiet >/dev/null

step "Result"
python3 - "$demo/result/report.json" "$demo/eval.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
e = json.load(open(sys.argv[2]))
b, t = r["betti"], e.get("truth_betti")
words = f"{b[0]} piece{'s' if b[0] != 1 else ''}, {b[1]} tunnel{'s' if b[1] != 1 else ''}, {b[2]} cavit{'ies' if b[2] != 1 else 'y'}"
print(f"object:    a torus (radii 12 and 4 mm) seen by {r['counts']['slices_used']} slices")
print(f"topology:  {words} (Betti numbers {b[0]} {b[1]} {b[2]}); the truth's are {t[0]} {t[1]} {t[2]}: "
      + ("right" if b == t else "WRONG"))
print(f"accuracy:  Hausdorff distance {e['hausdorff_mm']:.2f} mm, mean distance {e['mean_distance_mm']:.2f} mm, "
      f"Dice {e['dice']:.3f}; every slice's cut matches its section with IoU >= {e['conformity_iou_min']:.3f}")
import textwrap
print("verdict:   " + f"sampling {r['sampling']['verdict']}, topology confidence {r['topology']['confidence']['level']}: ")
print(textwrap.fill(r["in_plain_words"], width=100, initial_indent=" " * 11, subsequent_indent=" " * 11))
print(f"time:      {r['timings_s']['total']:.1f} s")
PY
cat <<EOF
report:    $demo/result/report.html
           open it in any browser (it works offline): xdg-open $demo/result/report.html
outputs:   $demo/result: mesh.ply (ParaView, MeshLab, Blender), labels.nrrd (3D Slicer: a label map),
           level_set.vdb (ParaView, Houdini), report.json, graph.json; what each holds: docs/outputs.md
next:      your own data: README.md, "Your own data"
EOF
