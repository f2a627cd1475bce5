#!/usr/bin/env python3
"""Issue 29's dominance figure over several `vdbmesh compare --json` reports, as one table.

`compare` itself decides which rows of ours beat each volumeToMesh row (no more triangles, no
larger Hausdorff distance, no larger share of angles under 10 degrees, clean, and no slower; at
adaptivity 1 up to 1.5x its time: find_dominance() in compare.h) and writes it as the report's
"dominance" list. This prints that list for every report as one markdown table.

    bench/dominance.py bunny.json cthead.json engine.json walnut.json

Exit status 0 when every volumeToMesh row of every report is dominated with time, 1 otherwise.
"""
import argparse
import json
import os
import sys


def label(mesh):
    """A row as compare's table names it."""
    if mesh["method"] == "openvdb":
        return f"openvdb a{mesh['adaptivity']:g}"
    if mesh.get("triangle_budget") is not None:
        return f"budget <= {mesh['triangle_budget']}"
    if mesh.get("decimate") is not None:
        return f"decimate {mesh['decimate']:g}"
    if mesh.get("error") is not None:
        return ("sharp " if mesh.get("sharp") else f"{mesh['method']} ") + f"{mesh['error']:g}"
    return mesh["method"]


def figures(mesh):
    return (f"{mesh['triangles']:,} / {mesh['hausdorff_voxels']:.3f} / "
            f"{100 * mesh['small_angle_share']:.3f}% / {mesh['seconds']:.3f} s")


def table_rows(name, report):
    meshes = report["meshes"]
    for d in report["dominance"]:
        anchor = meshes[d["volume_to_mesh"]]
        with_time = ", ".join(label(meshes[i]) for i in d["with_time"]) or "none"
        every_count = ", ".join(label(meshes[i]) for i in d["every_count"]) or "none"
        closest = ""
        if d["closest"] is not None:
            mesh = meshes[d["closest"]]
            closest = f"{label(mesh)} ({figures(mesh)}) loses on {', '.join(d['closest_loses'])}"
        yield f"| {name} | a{anchor['adaptivity']:g} | {figures(anchor)} | {with_time} | {every_count} | {closest} |"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reports", nargs="+", help="compare --json files")
    args = parser.parse_args()
    print("| scan | volumeToMesh | its triangles / Hausdorff / angles < 10 deg / time | dominated with time by "
          "| ignoring time by | closest when none |")
    print("|---|---|---|---|---|---|")
    every_one = True
    for path in args.reports:
        with open(path) as f:
            report = json.load(f)
        every_one = every_one and all(d["with_time"] for d in report["dominance"])
        for line in table_rows(os.path.splitext(os.path.basename(path))[0], report):
            print(line)
    return 0 if every_one else 1


if __name__ == "__main__":
    sys.exit(main())
