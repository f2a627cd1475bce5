#!/usr/bin/env python3
"""Label maps to meshes: `vdbmesh mesh --labels all` against 3D Slicer's export pipeline in VTK
(per label vtkDiscreteFlyingEdges3D, then vtkWindowedSincPolyDataFilter with Slicer's defaults:
20 iterations, pass band 10^(-4 x 0.5), normalised coordinates, no boundary or feature-edge
smoothing; no decimation), timed in the same run on the staged atlases, both judged by
vdbmesh_labels_bench (CGAL: each label's mesh; crossings between labels; volumes).

Needs python3-vtk9 (Debian 12: `apt-get install python3-vtk9`, run with /usr/bin/python3) and a
build with vdbmesh and vdbmesh_labels_bench. Each is run --repeat times in turns (the machine's load, when shared, falls on both); the
median wall and CPU seconds are reported, and each run's ratio of our time to VTK's. Usage:
    /usr/bin/python3 bench/labels_vs_vtk.py [--build build] [--threads 2] [--repeat 5]
"""

import argparse
import json
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import vtk

ATLASES = ["aal.nii.gz", "JHU-WhiteMatter-labels-1mm.nii.gz"]


def data_dir(repo):
    """$VDBMESH_DATA_DIR, else shared/data beside the repository or one of its parents (as
    tests/common/shared_data_dir.cpp looks)."""
    env = os.environ.get("VDBMESH_DATA_DIR")
    if env:
        return pathlib.Path(env)
    for folder in [repo, *repo.parents]:
        if (folder.parent / "shared" / "data").is_dir():
            return folder.parent / "shared" / "data"
    return repo.parent / "shared" / "data"


def cpu_seconds(who):
    """User and system seconds so far of this process (who=RUSAGE_SELF) or its waited-for children."""
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def vtk_pipeline(path, out_dir):
    """Slicer's closed-surface conversion per label; returns (seconds, CPU seconds, labels), without writing."""
    start, cpu_start = time.perf_counter(), cpu_seconds(resource.RUSAGE_SELF)
    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(str(path))
    reader.Update()
    image = reader.GetOutput()
    # Slicer pads the labelmap by one voxel so that surfaces close at the image border.
    pad = vtk.vtkImageConstantPad()
    pad.SetInputData(image)
    extent = image.GetExtent()
    pad.SetOutputWholeExtent(extent[0] - 1, extent[1] + 1, extent[2] - 1, extent[3] + 1, extent[4] - 1, extent[5] + 1)
    pad.SetConstant(0)
    pad.Update()
    padded = pad.GetOutput()
    scalars = vtk.util.numpy_support.vtk_to_numpy(padded.GetPointData().GetScalars())
    labels = sorted(int(v) for v in set(scalars.tolist()) if v != 0)
    meshes = {}
    for label in labels:
        flying = vtk.vtkDiscreteFlyingEdges3D()
        flying.SetInputData(padded)
        flying.SetValue(0, label)
        flying.ComputeGradientsOff()
        flying.ComputeNormalsOff()
        flying.ComputeScalarsOff()
        smoother = vtk.vtkWindowedSincPolyDataFilter()
        smoother.SetInputConnection(flying.GetOutputPort())
        smoother.SetNumberOfIterations(20)
        smoother.SetPassBand(pow(10.0, -4.0 * 0.5))
        smoother.BoundarySmoothingOff()
        smoother.FeatureEdgeSmoothingOff()
        smoother.NonManifoldSmoothingOn()
        smoother.NormalizeCoordinatesOn()
        smoother.Update()
        meshes[label] = smoother.GetOutput()
    seconds, cpu = time.perf_counter() - start, cpu_seconds(resource.RUSAGE_SELF) - cpu_start
    for label, mesh in meshes.items():
        writer = vtk.vtkSTLWriter()
        writer.SetFileName(str(out_dir / f"{label}.stl"))
        writer.SetInputData(mesh)
        writer.SetFileTypeToBinary()
        writer.Write()
    return seconds, cpu, len(labels)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=5, help="runs of each, in turns; the medians are reported")
    args = parser.parse_args()
    repo = pathlib.Path(__file__).resolve().parent.parent
    build = (repo / args.build).resolve()
    import vtk.util.numpy_support  # noqa: F401  (vtk_to_numpy)
    vtk.vtkSMPTools.SetBackend("STDThread")
    vtk.vtkSMPTools.Initialize(args.threads)
    rows = []
    for name in ATLASES:
        atlas = data_dir(repo) / "nifti_mricron_label_atlases" / name
        if not atlas.exists():
            print(f"skipped (missing): {atlas}", file=sys.stderr)
            continue
        ours, theirs = [], []  # per run: (seconds, CPU seconds, seconds without writing)
        with tempfile.TemporaryDirectory() as tmp:
            ours_dir, vtk_dir = pathlib.Path(tmp) / "ours", pathlib.Path(tmp) / "vtk"
            vtk_dir.mkdir()
            # Taken in turns, so that a change of the machine's load falls on both.
            for _ in range(args.repeat):
                start, cpu_start = time.perf_counter(), cpu_seconds(resource.RUSAGE_CHILDREN)
                report = json.loads(subprocess.run([str(build / "vdbmesh"), "mesh", str(atlas), "--labels", "all", "-o", str(ours_dir) + "/",
                                                    "--json", "-q", "--threads", str(args.threads)], check=True, capture_output=True, text=True).stdout)
                seconds = time.perf_counter() - start
                # Like VTK's time, also without writing the files (ours syncs each to disk before its rename).
                writing = sum(p["seconds"] for p in report["phases"] if p["name"] == "write")
                ours.append((seconds, cpu_seconds(resource.RUSAGE_CHILDREN) - cpu_start, seconds - writing))
                seconds, cpu, _ = vtk_pipeline(atlas, vtk_dir)
                theirs.append((seconds, cpu, seconds))
            judged = [json.loads(line) for line in subprocess.run([str(build / "bench" / "vdbmesh_labels_bench"), str(atlas), str(ours_dir), str(vtk_dir)],
                                                                    check=True, capture_output=True, text=True).stdout.splitlines()]
        for who, runs, j in (("vdbmesh", ours, judged[0]), ("vtk", theirs, judged[1])):
            median = lambda i: round(statistics.median(run[i] for run in runs), 3)  # noqa: E731
            row = {"atlas": name, "mesher": who, "seconds": median(0), "cpu_seconds": median(1), "runs": [round(run[0], 3) for run in runs],
                   **{k: v for k, v in j.items() if k != "folder"}}
            if who == "vdbmesh":
                row["seconds_without_writing"] = median(2)
                row["relabelled_voxels"] = report["relabelled_voxels"]
                row["vertices_held_back"] = report["vertices_held_back"]
            rows.append(row)
            print(json.dumps(row), flush=True)
        ratios = [o[0] / t[0] for o, t in zip(ours, theirs)]
        print(json.dumps({"atlas": name, "time_over_vtk_per_run": [round(r, 2) for r in ratios], "median": round(statistics.median(ratios), 2)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
