#!/usr/bin/env python3
"""vdbmesh.mesh and vdbmesh.marching_cubes against skimage.measure.marching_cubes on the Stanford CT bunny, in one process.

Reads the bunny (../shared/data/raw_stanford_ct_bunny, two gzip parts of big-endian 16-bit
samples, 512 x 512 x 361; the padding outside the field of view, 0xF830, is -2000 only as
int16) into a float32 array a[z, y, x] of shape 361 x 512 x 512, meshes it at 1200.5 with
each, `--repeat` times (the best time counts: the first call also pays for first
touches of memory and, for vdbmesh, starting its threads), and prints the times, their
ratio, the triangle counts and whether each mesh is closed (vdbmesh.check).

Usage (the module built, Debian's python3 for numpy and scikit-image):
    PYTHONPATH=build/python /usr/bin/python3 bench/python_vs_skimage.py [--repeat 2]
"""

import argparse
import gzip
import os
import sys
import time
from pathlib import Path

import numpy as np
from skimage import measure

import vdbmesh

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python" / "tests"))
from shared_data import shared_data_dir  # noqa: E402  (the tests' one finder of shared data)

SHAPE = (361, 512, 512)
ISO = 1200.5
PARTS = [f"raw_stanford_ct_bunny/bunny_ct_512x512x361_uint16be.part{n}of2.raw.gz" for n in (1, 2)]


def read_bunny():
    folder = shared_data_dir()
    if folder is None or not all((folder / part).exists() for part in PARTS):
        sys.exit("the bunny CT is missing: ../shared/data beside the checkout, or set VDBMESH_DATA_DIR")
    raw = b"".join(gzip.decompress((folder / part).read_bytes()) for part in PARTS)
    return np.frombuffer(raw, dtype=">i2").reshape(SHAPE).astype(np.float32)


def best_time(mesher, volume, repeat):
    """(best wall seconds, every run's (wall, CPU) seconds, the last result). CPU seconds are
    those of the whole process, all threads: on a shared machine they show the work done."""
    runs = []
    for _ in range(repeat):
        start, start_cpu = time.perf_counter(), time.process_time()
        result = mesher(volume)
        runs.append((time.perf_counter() - start, time.process_time() - start_cpu))
    return min(wall for wall, _ in runs), runs, result


def describe(name, seconds, runs, vertices, faces):
    figures = vdbmesh.check(vertices, faces)
    listed = ", ".join(f"{wall:.3f} ({cpu:.3f} CPU)" for wall, cpu in runs)
    print(f"{name:>8}: {seconds:.3f} s (runs: wall (CPU) {listed}), {len(faces)} triangles, {len(vertices)} vertices, "
          f"closed {figures['closed']} ({figures['boundary_edges']} boundary edges)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=2, help="runs per mesher, the best counts (default 2)")
    args = parser.parse_args()

    start = time.perf_counter()
    volume = read_bunny()
    print(f"bunny: {volume.shape} {volume.dtype}, read in {time.perf_counter() - start:.2f} s; iso {ISO}; "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}")

    ours, our_times, (vertices, faces) = best_time(lambda a: vdbmesh.mesh(a, ISO), volume, args.repeat)
    drop_in, drop_in_times, (mc_vertices, mc_faces, _, _) = best_time(lambda a: vdbmesh.marching_cubes(a, ISO), volume,
                                                                       args.repeat)
    theirs, their_times, (sk_vertices, sk_faces, _, _) = best_time(lambda a: measure.marching_cubes(a, ISO), volume,
                                                                    args.repeat)
    describe("vdbmesh", ours, our_times, vertices, faces)
    describe("drop-in", drop_in, drop_in_times, mc_vertices, mc_faces)
    describe("skimage", theirs, their_times, sk_vertices.astype(np.float32), sk_faces)
    print(f"drop-in / skimage: {drop_in / theirs:.3f} wall, "
          f"{min(cpu for _, cpu in drop_in_times) / min(cpu for _, cpu in their_times):.3f} CPU")
    ratio = ours / theirs
    cpu_ratio = min(cpu for _, cpu in our_times) / min(cpu for _, cpu in their_times)
    print(f"ratio vdbmesh / skimage: {ratio:.3f} wall (target <= 0.333: {'met' if ratio <= 1 / 3 else 'NOT met'}), "
          f"{cpu_ratio:.3f} CPU")


if __name__ == "__main__":
    main()
