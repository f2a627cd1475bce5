#!/usr/bin/env python3
"""Writes the Stanford bunny CT tiled k x k x k into one headerless raw file, for the scale rows
of bench/README.md (issue 28): 512k x 512k x 361k samples, u16 big-endian as the original.

    bench/make_tiled_scan.py --k 3 -o /scratch/bunny_k3.raw
    vdbmesh mesh /scratch/bunny_k3.raw --raw-dims 1536,1536,1083 --raw-type i16 --raw-endian big \\
        --iso 1200.5 --error 0.25 -o bunny_k3.ply

The original (189 MB, from the two gzip members in the shared data folder) is held in memory;
the tiled file is streamed one z-slice at a time (k = 6 is 41 GB and is never held), written
to a temporary name beside the output and renamed at the end, so a cut run leaves no file
that looks complete. The standard library only (no numpy on the bench machines).
"""

import argparse
import gzip
import os
import sys

DIMS = (512, 512, 361)
SAMPLE_BYTES = 2
PARTS = ("bunny_ct_512x512x361_uint16be.part1of2.raw.gz", "bunny_ct_512x512x361_uint16be.part2of2.raw.gz")


def shared_data_dir():
    """$VDBMESH_DATA_DIR, else shared/data beside the checkout or one of its parents (as
    tests/common/shared_data_dir.cpp looks for it)."""
    if os.environ.get("VDBMESH_DATA_DIR"):
        return os.environ["VDBMESH_DATA_DIR"]
    folder = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    while os.path.dirname(folder) != folder:
        candidate = os.path.join(os.path.dirname(folder), "shared", "data")
        if os.path.isdir(candidate):
            return candidate
        folder = os.path.dirname(folder)
    return ""


def read_original(folder):
    data = bytearray()
    for part in PARTS:
        with gzip.open(os.path.join(folder, part), "rb") as stream:
            data += stream.read()
    expected = DIMS[0] * DIMS[1] * DIMS[2] * SAMPLE_BYTES
    if len(data) != expected:
        sys.exit(f"{folder}: the bunny CT holds {len(data)} bytes, expected {expected} (512 x 512 x 361 u16)")
    return bytes(data)


def tiled_slice(original, z, k):
    """Slice z of the tiled volume: source slice z mod 361, each row repeated k times in x, the rows k times in y."""
    row_bytes = DIMS[0] * SAMPLE_BYTES
    start = (z % DIMS[2]) * DIMS[1] * row_bytes
    rows = b"".join(original[start + y * row_bytes:start + (y + 1) * row_bytes] * k for y in range(DIMS[1]))
    return rows * k


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--k", type=int, required=True, help="tiles per axis (1, 2, 3, 6 for the bench)")
    parser.add_argument("-o", "--output", required=True, help="the raw file to write")
    parser.add_argument("--data", default=shared_data_dir(), help="the shared data folder (default: %(default)s)")
    parser.add_argument("--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args()
    if args.k < 1:
        parser.error(f"--k: expected a positive number of tiles, got {args.k}")
    original = read_original(os.path.join(args.data, "raw_stanford_ct_bunny"))
    slices = DIMS[2] * args.k
    temporary = args.output + ".part"
    progress = sys.stderr.isatty() and not args.quiet
    with open(temporary, "wb") as out:
        for z in range(slices):
            out.write(tiled_slice(original, z, args.k))
            if progress and z % 16 == 0:
                print(f"\r{z * 100 // slices}%", end="", file=sys.stderr, flush=True)
    os.replace(temporary, args.output)
    if progress:
        print("\r100%", file=sys.stderr)
    dims = ",".join(str(d * args.k) for d in DIMS)
    print(f"{args.output}: {dims} samples, u16 big-endian (vdbmesh: --raw-dims {dims} --raw-type i16 --raw-endian big)")


if __name__ == "__main__":
    main()
