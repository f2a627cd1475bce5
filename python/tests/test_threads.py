"""The library releases the GIL while it works: other Python threads run meanwhile."""

import math
import threading
import time

import vdbmesh
from volumes import sphere_field


def test_python_threads_run_while_a_mesh_is_made():
    volume = sphere_field(160, 70.0)
    start = time.perf_counter()
    vdbmesh.mesh(volume, 0.0)
    alone = time.perf_counter() - start
    # Enough calls to keep the worker busy for about 0.2 s, however fast the machine.
    repeats = max(1, math.ceil(0.2 / max(alone, 1e-3)))

    def work():
        for _ in range(repeats):
            vdbmesh.mesh(volume, 0.0)

    ticks = 0
    worker = threading.Thread(target=work)
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Holding the GIL, each call would let this loop tick only between calls (at most a few
    # times per call). Released, the loop ticks about once a millisecond all along: 100 or
    # more in 0.2 s; on a machine loaded by parallel builds it was seen under 10, so the
    # bound is 2 ticks per call plus 5.
    assert ticks >= 2 * repeats + 5
