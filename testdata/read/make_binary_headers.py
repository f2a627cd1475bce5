#!/usr/bin/env python3
"""Writes the tiny Analyze 7.5 / NIfTI-1 files of this folder (run it here to regenerate them).

Byte offsets are those of the 348-byte header (Mayo Analyze 7.5 dbh.h, NIfTI-1 nifti1.h).
The expected values in tests/read/nifti_analyze_test.cpp follow from the formulas below.
"""
import gzip
import math
import struct


def header(order, dims, datatype, bitpix, pixdim, vox_offset, magic=b"", slope=0.0, inter=0.0,
           xyzt_units=0, qform_code=0, sform_code=0, quatern=(0, 0, 0), qoffset=(0, 0, 0),
           srow=((0,) * 4,) * 3, vox_units=b"", originator=None):
    h = bytearray(348)
    struct.pack_into(order + "i", h, 0, 348)
    struct.pack_into(order + "8h", h, 40, *(list(dims) + [1] * (8 - len(dims))))
    h[56:56 + len(vox_units)] = vox_units
    struct.pack_into(order + "hh", h, 70, datatype, bitpix)
    struct.pack_into(order + "8f", h, 76, *(list(pixdim) + [0.0] * (8 - len(pixdim))))
    struct.pack_into(order + "fff", h, 108, vox_offset, slope, inter)
    h[123] = xyzt_units
    struct.pack_into(order + "hh", h, 252, qform_code, sform_code)
    struct.pack_into(order + "6f", h, 256, *quatern, *qoffset)
    struct.pack_into(order + "12f", h, 280, *[v for row in srow for v in row])
    if originator is not None:  # Analyze/SPM: bytes 253..258, where NIfTI has its form codes
        struct.pack_into(order + "3h", h, 253, *originator)
    h[344:344 + len(magic)] = magic
    return bytes(h)


def samples(order, fmt, dims, value):
    nx, ny, nz = dims
    return b"".join(struct.pack(order + fmt, value(x, y, z))
                    for z in range(nz) for y in range(ny) for x in range(nx))


def write(name, data):
    with open(name, "wb") as f:
        f.write(data)


# Big-endian Analyze 7.5 pair, i16, SPM scale 0.5 in funused1, originator (2, 3, 1).
write("analyze_be_i16.hdr", header(">", (3, 4, 3, 2), 4, 16, (0, 1.5, 2, 2.5), 0, slope=0.5,
                                   vox_units=b"mm", originator=(2, 3, 1)))
write("analyze_be_i16.img", samples(">", "h", (4, 3, 2), lambda x, y, z: x + 10 * y + 100 * z - 50))

# NIfTI-1 pair ("ni1"), little-endian f32, sform: a 90-degree turn about z, spacing (1, 2, 3).
write("nifti_pair_f32.hdr", header("<", (3, 3, 2, 2), 16, 32, (1, 1, 1, 1), 0, magic=b"ni1\0",
                                   xyzt_units=2, sform_code=2,
                                   srow=((0, -2, 0, 5), (1, 0, 0, 6), (0, 0, 3, 7))))
write("nifti_pair_f32.img", samples("<", "f", (3, 2, 2), lambda x, y, z: 0.25 * (x + 3 * y + 6 * z) - 1))

# Single-file NIfTI-1 ("n+1"), u16, qform only: quaternion (0, 0, sin 45deg) = 90 degrees
# about z, qfac -1, pixdim (1, 2, 3), offsets (10, 20, 30), scl 2 / -1, units micron.
write("nifti_qform_u16.nii",
      header("<", (3, 3, 2, 2), 512, 16, (-1, 1, 2, 3), 352, magic=b"n+1\0", slope=2, inter=-1,
             xyzt_units=3, qform_code=1, quatern=(0, 0, math.sqrt(0.5)), qoffset=(10, 20, 30))
      + bytes(4) + samples("<", "H", (3, 2, 2), lambda x, y, z: 60000 + x + 3 * y + 6 * z))

# Gzipped 4-D NIfTI-1, 2x2x2x3 u8, no qform/sform (pixdim 0.5): only volume 0 is read.
volumes = b"".join(samples("<", "B", (2, 2, 2), lambda x, y, z, t=t: 100 * t + x + 2 * y + 4 * z)
                   for t in range(3))
write("nifti_4d_u8.nii.gz", gzip.compress(
    header("<", (4, 2, 2, 2, 3), 2, 8, (1, 0.5, 0.5, 0.5, 1), 352, magic=b"n+1\0") + bytes(4) + volumes,
    mtime=0))
