#!/usr/bin/env python3
"""The peak memory of `vdbmesh view INPUT --memory SIZE` once the page's background work is done
(issue 28 item 2): the splat tree's fit, then the histogram and coarse grid.

Starts the server under /usr/bin/time, asks it to prepare at once (GET /api/info?prepare=1, as
the page does once its first splats are drawn), waits until /api/info says the fit and the
preparation are done, then asks the splats of a camera on the whole model and the coarse mesh;
reads the server's VmHWM at each step, stops it with SIGINT and prints the times and peaks as
JSON. A benchmark, not a test.

    bench/view_memory_peak.py [--until-fitted] build/vdbmesh INPUT [VIEW ARGUMENTS ...]
    e.g. bench/view_memory_peak.py build/vdbmesh bunny_k3.vdb --memory 1G   (bench/make_tiled_scan.py, then convert)

--until-fitted stops the server once the fit is done (the preparation, a pass over the whole
grid that takes minutes on a huge scan, not waited for).
"""
import json
import os
import re
import struct
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from view_region_peak import ViewServer, camera, get  # noqa: E402


def hwm_mb(pid):
    """VmHWM of the process @a pid (vdbmesh under /usr/bin/time), in MiB."""
    with open(f"/proc/{pid}/status") as status:
        return round(int(re.search(r"VmHWM:\s+(\d+)", status.read()).group(1)) / 1024)


def child_pid(pid):
    with open(f"/proc/{pid}/task/{pid}/children") as children:
        return int(children.read().split()[0])


def main():
    arguments = sys.argv[1:]
    until_fitted = bool(arguments) and arguments[0] == "--until-fitted"
    if until_fitted:
        arguments = arguments[1:]
    if len(arguments) < 2:
        sys.exit(__doc__)
    command = ["/usr/bin/time", "-f", "peak_kb %M", arguments[0], "view", *arguments[1:], "--no-open", "--quiet"]
    start = time.monotonic()
    with ViewServer(command) as server:
        base = server.base
        pid = child_pid(server.process.pid)
        report = {"command": " ".join(command[3:]), "serving_s": round(time.monotonic() - start, 2)}
        info = json.loads(get(base, "/api/info?prepare=1")[0])
        report["preview_nodes"] = info.get("splats", {}).get("nodes")
        report["hwm_mb_loaded"] = hwm_mb(pid)
        fitted = False
        while True:
            info = json.loads(get(base, "/api/info")[0])
            if "prepare_error" in info:
                report["prepare_error"] = info["prepare_error"]
                break
            splats = info.get("splats", {})
            if not fitted and not splats.get("preview", False):
                fitted = True
                report["fit_s"] = splats.get("seconds")
                report["fitted_nodes"] = splats.get("nodes")
                report["fitted_at_s"] = round(time.monotonic() - start, 2)
                report["hwm_mb_fitted"] = hwm_mb(pid)
                report["finest_kept"] = splats.get("finest_kept")
            if fitted and (until_fitted or not info.get("preparing", False)):
                break
            time.sleep(0.5)
        if not until_fitted:
            report["prepared_at_s"] = round(time.monotonic() - start, 2)
            report["hwm_mb_prepared"] = hwm_mb(pid)
        if "prepare_error" not in report and not until_fitted:
            body, headers, seconds = get(base, "/api/mesh?level=coarse")
            vertices = int(headers["X-Vertices"])
            positions = struct.unpack(f"<{3 * vertices}f", body[: 12 * vertices])
            lo = [min(positions[a::3]) for a in range(3)]
            hi = [max(positions[a::3]) for a in range(3)]
            report["coarse_triangles"] = int(headers["X-Triangles"])
            vp, eye, focal = camera(lo, hi)
            query = "vp=" + ",".join(f"{v:.9g}" for v in vp) + "&eye=" + ",".join(f"{v:.9g}" for v in eye) + f"&focal={focal:.9g}"
            _, headers, seconds = get(base, "/api/splats?" + query)
            report["splats"] = {"shown": int(headers["X-Splats"]), "level": int(headers["X-Level"]),
                                "tree_nodes": int(headers["X-Tree-Nodes"]), "s": round(seconds, 2)}
        report["peak_mb"] = server.stop()
    report["total_s"] = round(time.monotonic() - start, 2)
    with open("/proc/loadavg") as load:
        report["load_after"] = load.read().split()[0]
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
