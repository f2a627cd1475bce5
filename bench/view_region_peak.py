#!/usr/bin/env python3
"""The peak memory of `vdbmesh view GRID.vdb` serving what the page asks of a huge model (issue 30).

Starts the server under /usr/bin/time, then asks, as the page does: /api/info, the coarse mesh,
the splats of a camera looking at the whole model (which builds the splat tree, read by region),
and the triangles of one region (a close-up, level=region); stops the server with SIGINT and
prints each answer's time and counts and the server's peak RSS as JSON. A benchmark, not a test.

    bench/view_region_peak.py build/tools/vdbmesh GRID.vdb [--box x0,y0,z0,x1,y1,z1] [--iso V]
"""
import argparse
import json
import os
import re
import signal
import struct
import subprocess
import sys
import time
import urllib.request


def get(base, path):
    start = time.monotonic()
    with urllib.request.urlopen(base + path, timeout=3600) as response:
        body = response.read()
        return body, dict(response.headers), time.monotonic() - start


class ViewServer:
    """`vdbmesh view` (@a command, under /usr/bin/time -f "peak_kb %M") for a with-block: started
    in its own session, and stopped at the block's end even when a request in it fails (a
    failed request used to leave the server running)."""

    def __init__(self, command):
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                        start_new_session=True)
        self.errors = None
        line = self.process.stdout.readline()
        match = re.search(r"(http://[^ ]+/)", line)
        if not match:
            self.process.kill()
            sys.exit("the server did not start: " + line + self.process.stderr.read())
        self.base = match.group(1).rstrip("/")

    def __enter__(self):
        return self

    def __exit__(self, *failure):
        self.stop()
        return False

    def stop(self):
        """Stops the server (once) and returns its peak resident memory in MB, None if not reported."""
        if self.errors is None:
            os.killpg(self.process.pid, signal.SIGINT)  # to vdbmesh: GNU time ignores it while it waits
            _, self.errors = self.process.communicate(timeout=600)
        peak = re.search(r"peak_kb (\d+)", self.errors)
        return round(int(peak.group(1)) / 1024) if peak else None


def camera(lo, hi):
    """An orthographic camera on +z looking at the box [lo, hi]: world to clip, column-major."""
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    half = max(b - a for a, b in zip(lo, hi)) / 2 * 1.1
    vp = [0.0] * 16
    for axis in range(3):
        vp[axis * 5] = 1 / half if axis < 2 else -1 / (4 * half)
        vp[12 + axis] = -centre[axis] / half if axis < 2 else centre[axis] / (4 * half)
    vp[15] = 1.0
    eye = [centre[0], centre[1], centre[2] + 3 * half]
    return vp, eye, 350.0 / half


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("vdbmesh")
    parser.add_argument("grid")
    parser.add_argument("--box", default="704,704,448,832,832,576")
    parser.add_argument("--iso")
    args = parser.parse_args()
    command = ["/usr/bin/time", "-f", "peak_kb %M", args.vdbmesh, "view", args.grid, "--no-open", "--quiet"]
    if args.iso:
        command += ["--iso", args.iso]
    start = time.monotonic()
    with ViewServer(command) as server:
        base = server.base
        report = {"grid": args.grid, "serving_s": round(time.monotonic() - start, 2)}
        _, _, seconds = get(base, "/api/info")
        body, headers, seconds = get(base, "/api/mesh?level=coarse")
        vertices = int(headers["X-Vertices"])
        positions = struct.unpack(f"<{3 * vertices}f", body[: 12 * vertices])
        lo = [min(positions[a::3]) for a in range(3)]
        hi = [max(positions[a::3]) for a in range(3)]
        report["coarse"] = {"triangles": int(headers["X-Triangles"]), "s": round(seconds, 2)}
        vp, eye, focal = camera(lo, hi)
        query = "vp=" + ",".join(f"{v:.9g}" for v in vp) + "&eye=" + ",".join(f"{v:.9g}" for v in eye) + f"&focal={focal:.9g}"
        _, headers, seconds = get(base, "/api/splats?" + query)
        report["splats"] = {"shown": int(headers["X-Splats"]), "level": int(headers["X-Level"]),
                            "tree_nodes": int(headers["X-Tree-Nodes"]), "tree_s": float(headers["X-Seconds"]),
                            "s": round(seconds, 2)}
        _, headers, seconds = get(base, f"/api/mesh?level=region&method=dc&error=0.25&box={args.box}")
        report["region"] = {"box": args.box, "triangles": int(headers["X-Triangles"]), "s": round(seconds, 2)}
        report["peak_mb"] = server.stop()
    report["total_s"] = round(time.monotonic() - start, 2)
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
