"""The cohort's table and index page from its subjects' status.json and run outputs
(workflows/cohort/Snakefile; docs/cohorts.md)."""

import csv
import html
import json
import os

import numpy as np

COLUMNS = ["id", "status", "exit_code", "b0", "b1", "b2", "verdict", "confidence", "volume_mm3",
           "surface_area_mm2", "run_s", "wall_s", "warnings", "report", "message"]


def ply_area(path):
    """The surface area (mm²) of a binary little-endian PLY as xsect writes it (float x y z, then
    faces as a uchar count and int indices)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    head = data[:end].decode("ascii").splitlines()
    if "format binary_little_endian 1.0" not in head:
        raise ValueError(f"{path}: not a binary little-endian PLY")
    nv = nf = 0
    vprops = []
    element = None
    for line in head:
        w = line.split()
        if w[:1] == ["element"]:
            element = w[1]
            if element == "vertex":
                nv = int(w[2])
            elif element == "face":
                nf = int(w[2])
        elif w[:1] == ["property"] and element == "vertex":
            if w[1] != "float":
                raise ValueError(f"{path}: vertex property {w[-1]} is not a float")
            vprops.append(w[-1])
    vertices = np.frombuffer(data, dtype="<f4", count=nv * len(vprops), offset=end).reshape(nv, len(vprops))[:, :3]
    faces = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("v", "<i4", 3)]), count=nf,
                          offset=end + 4 * nv * len(vprops))
    if nf and (faces["n"] != 3).any():
        raise ValueError(f"{path}: a face is not a triangle")
    a, b, c = (vertices[faces["v"][:, i]].astype(np.float64) for i in range(3))
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def subject_row(status):
    row = {k: "" for k in COLUMNS}
    row.update(id=status["id"], status=status["status"], exit_code=status["exit_code"],
               wall_s=status.get("wall_s", ""), message=status.get("message", ""))
    if status["status"] != "ok":
        return row
    result = status["result"]
    report = json.load(open(os.path.join(result, "report.json")))
    b = report["betti"]
    row.update(b0=b[0], b1=b[1], b2=b[2], verdict=report["sampling"]["verdict"],
               volume_mm3=report["reconstruction"].get("volume_mm3", ""),
               run_s=round(sum(v for k, v in report["timings_s"].items() if k != "total"), 3),
               warnings=len(report.get("warnings", [])),
               report=os.path.join(result, "report.html"))
    confidence = report.get("topology", {}).get("confidence")
    if isinstance(confidence, dict):
        row["confidence"] = confidence.get("level", "")
    meshes = [f for f in os.listdir(result) if f.startswith("mesh.")]
    if "mesh.ply" in meshes:
        row["surface_area_mm2"] = round(ply_area(os.path.join(result, "mesh.ply")), 6)
    return row


def write_table(rows, path):
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in sorted(rows, key=lambda r: r["id"]):
            # report.html's path relative to the table: the cohort's folder can move.
            w.writerow(dict(r, report=os.path.relpath(r["report"], os.path.dirname(path)) if r["report"] else ""))
    os.replace(path + ".tmp", path)


def write_index(rows, path, out):
    lines = ["<!doctype html><meta charset=utf-8><title>xsect cohort</title>",
             "<style>body{font:14px sans-serif;margin:2em}td,th{padding:2px 10px;text-align:left}"
             ".invalid{color:#a00}</style>",
             f"<h1>xsect cohort: {len(rows)} subjects</h1>",
             "<p>Table: <a href=cohort.csv>cohort.csv</a>. Betti numbers (components, tunnels, cavities), "
             "the sampling verdict and the topology's confidence are each run's report.json's.</p>",
             "<table><tr>" + "".join(f"<th>{c}</th>" for c in
                                     ["subject", "status", "Betti", "verdict", "confidence", "volume mm³", "message"]) + "</tr>"]
    for r in sorted(rows, key=lambda r: r["id"]):
        name = html.escape(r["id"])
        if r["report"]:
            name = f"<a href=\"{html.escape(os.path.relpath(r['report'], os.path.dirname(path)))}\">{name}</a>"
        betti = f"{r['b0']} {r['b1']} {r['b2']}" if r["status"] == "ok" else ""
        volume = f"{float(r['volume_mm3']):.1f}" if r["volume_mm3"] != "" else ""
        lines.append(f"<tr class={html.escape(r['status'])}><td>{name}<td>{html.escape(r['status'])}<td>{betti}"
                     f"<td>{html.escape(str(r['verdict']))}<td>{html.escape(str(r['confidence']))}<td>{volume}"
                     f"<td>{html.escape(str(r['message']))}</tr>")
    lines.append("</table>")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)
