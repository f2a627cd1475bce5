#!/usr/bin/env python3
"""Label maps to meshes: `vdbmesh mesh --labels all` against 3D Slicer's export pipeline in VTK
(per label vtkDiscreteFlyingEdges3D, then vtkWindowedSincPolyDataFilter with Slicer's defaults:
20 iterations, pass band 10^(-4 x 0.5), normalised coordinates, no boundary or feature-edge
smoothing; no decimation), timed in the same run on the staged atlases, both judged by
vdbmesh_labels_bench (CGAL: each label's mesh; crossings between labels; volumes).

Needs python3-vtk9 (Debian 12: `apt-get install python3-vtk9`, run with /usr/bin/python3) and a
build with vdbmesh and vdbmesh_labels_bench. Usage:
    /usr/bin/python3 bench/labels_vs_vtk.py [--build build] [--threads 2]
"""

import argparse
import json
import os
import pathlib
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


def vtk_pipeline(path, out_dir):
    """Slicer's closed-surface conversion per label; returns (seconds without writing, labels)."""
    start = time.perf_counter()
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
    seconds = time.perf_counter() - start
    for label, mesh in meshes.items():
        writer = vtk.vtkSTLWriter()
        writer.SetFileName(str(out_dir / f"{label}.stl"))
        writer.SetInputData(mesh)
        writer.SetFileTypeToBinary()
        writer.Write()
    return seconds, len(labels)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--threads", type=int, default=2)
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
        with tempfile.TemporaryDirectory() as tmp:
            ours_dir, vtk_dir = pathlib.Path(tmp) / "ours", pathlib.Path(tmp) / "vtk"
            vtk_dir.mkdir()
            start = time.perf_counter()
            report = json.loads(subprocess.run([str(build / "vdbmesh"), "mesh", str(atlas), "--labels", "all", "-o", str(ours_dir) + "/",
                                                "--json", "-q", "--threads", str(args.threads)], check=True, capture_output=True, text=True).stdout)
            ours_seconds = time.perf_counter() - start
            vtk_seconds, vtk_labels = vtk_pipeline(atlas, vtk_dir)
            judged = [json.loads(line) for line in subprocess.run([str(build / "bench" / "vdbmesh_labels_bench"), str(atlas), str(ours_dir), str(vtk_dir)],
                                                                    check=True, capture_output=True, text=True).stdout.splitlines()]
        for who, seconds, j in (("vdbmesh", ours_seconds, judged[0]), ("vtk", vtk_seconds, judged[1])):
            row = {"atlas": name, "mesher": who, "seconds": round(seconds, 3), **{k: v for k, v in j.items() if k != "folder"}}
            if who == "vdbmesh":
                # Like VTK's time: without writing the files (ours syncs each to disk before its rename).
                writing = sum(p["seconds"] for p in report["phases"] if p["name"] == "write")
                row["seconds_without_writing"] = round(seconds - writing, 3)
                row["relabelled_voxels"] = report["relabelled_voxels"]
                row["vertices_held_back"] = report["vertices_held_back"]
            rows.append(row)
            print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
