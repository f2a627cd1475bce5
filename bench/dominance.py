#!/usr/bin/env python3
"""Which volumeToMesh meshes a mesh of ours dominates, from `vdbmesh compare --json` reports.

Issue 29's figure: every volumeToMesh mesh is dominated by a mesh of ours, that is one with no
more triangles, no larger two-sided Hausdorff distance, no larger share of angles under 10
degrees, no defect (compare's `clean`: closed, manifold, outward, no self-intersecting or
degenerate triangle) and no more time; at adaptivity 1 the time may be up to 1.5x. Every row of
ours in the report is a candidate (DC at each error, Marching Cubes, the budget rows, the sharp
rows). For each volumeToMesh mesh this prints the rows that dominate it without and with time,
and when none does with time, the row that comes closest and the counts it loses on.

    bench/dominance.py bunny.json cthead.json engine.json walnut.json [--markdown]

Exit status 0 when every volumeToMesh mesh of every report is dominated with time, 1 otherwise.
"""
import argparse
import json
import os
import sys

ADAPTIVITY_ONE_TIME_FACTOR = 1.5  # issue 29: "at adaptivity 1: at most 1.5x" volumeToMesh's time


def label(mesh):
    """How compare's table names a row."""
    if mesh["method"] == "openvdb":
        return f"openvdb a{mesh['adaptivity']:g}"
    if mesh.get("triangle_budget") is not None:
        return f"budget <= {mesh['triangle_budget']}"
    if mesh.get("decimate") is not None:
        return f"decimate {mesh['decimate']:g}"
    if mesh["method"] == "dc" and mesh.get("error") is not None:
        return ("sharp " if mesh.get("sharp") else "dc ") + f"{mesh['error']:g}"
    return mesh["method"]


def time_allowed(anchor):
    factor = ADAPTIVITY_ONE_TIME_FACTOR if anchor["adaptivity"] >= 1 else 1.0
    return factor * anchor["seconds"]


def lost_counts(ours, anchor):
    """The counts on which @p ours does not beat-or-tie @p anchor (empty: it dominates)."""
    lost = []
    if ours["triangles"] > anchor["triangles"]:
        lost.append("triangles")
    if ours["hausdorff_voxels"] > anchor["hausdorff_voxels"]:
        lost.append("hausdorff")
    if ours["small_angle_share"] > anchor["small_angle_share"]:
        lost.append("angles")
    if not ours["clean"]:
        lost.append("defects")
    if ours["seconds"] > time_allowed(anchor):
        lost.append("time")
    return lost


def judge_report(report):
    """One line of figures per volumeToMesh mesh of @p report, and whether each is dominated."""
    meshes = report["meshes"]
    ours = [m for m in meshes if m["method"] != "openvdb"]
    rows = []
    for anchor in (m for m in meshes if m["method"] == "openvdb"):
        verdicts = [(m, lost_counts(m, anchor)) for m in ours]
        with_time = [label(m) for m, lost in verdicts if not lost]
        without_time = [label(m) for m, lost in verdicts if not [c for c in lost if c != "time"]]
        closest = min(verdicts, key=lambda v: (len(v[1]), v[0]["triangles"]))
        rows.append({
            "anchor": anchor,
            "with_time": with_time,
            "without_time": without_time,
            "closest": closest,
        })
    return rows


def figures(mesh):
    return (f"{mesh['triangles']:,} tri, H {mesh['hausdorff_voxels']:.3f}, "
            f"<10deg {100 * mesh['small_angle_share']:.3f}%, {mesh['seconds']:.3f} s")


def print_rows(name, rows, markdown):
    for row in rows:
        anchor = row["anchor"]
        verdict = ", ".join(row["with_time"]) if row["with_time"] else "none"
        if markdown:
            closest, lost = row["closest"]
            miss = "" if row["with_time"] else f"closest {label(closest)} ({figures(closest)}) loses {'/'.join(lost)}"
            print(f"| {name} | a{anchor['adaptivity']:g} | {figures(anchor)} | {verdict} | "
                  f"{', '.join(row['without_time']) or 'none'} | {miss} |")
        else:
            print(f"{name:8} {label(anchor):12} {figures(anchor)}")
            print(f"{'':8} dominated with time by: {verdict}; ignoring time by: "
                  f"{', '.join(row['without_time']) or 'none'}")
            if not row["with_time"]:
                closest, lost = row["closest"]
                print(f"{'':8} closest: {label(closest)} ({figures(closest)}), loses {'/'.join(lost)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reports", nargs="+", help="compare --json files")
    parser.add_argument("--markdown", action="store_true", help="one table row per volumeToMesh mesh")
    args = parser.parse_args()
    if args.markdown:
        print("| scan | volumeToMesh | its figures | dominated with time by | ignoring time by | closest when none |")
        print("|---|---|---|---|---|---|")
    every_one = True
    for path in args.reports:
        with open(path) as f:
            report = json.load(f)
        rows = judge_report(report)
        every_one = every_one and all(row["with_time"] for row in rows)
        print_rows(os.path.splitext(os.path.basename(path))[0], rows, args.markdown)
    return 0 if every_one else 1


if __name__ == "__main__":
    sys.exit(main())
