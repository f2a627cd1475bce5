"""The library releases the GIL while it works: other Python threads run meanwhile."""

import threading
import time

import vdbmesh
from volumes import sphere_field


def test_python_threads_run_while_a_mesh_is_made():
    volume = sphere_field(160, 70.0)
    start = time.perf_counter()
    vdbmesh.mesh(volume, 0.0)
    alone = time.perf_counter() - start

    ticks = 0
    worker = threading.Thread(target=vdbmesh.mesh, args=(volume, 0.0))
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    # Holding the GIL, the call would let this loop tick only before and after it (at most 2 or
    # 3 times). Released, the loop ticks about once a millisecond all along: 50 or more in a
    # call of 0.05 s or longer; on a machine loaded by parallel builds it was seen under 10,
    # so 5 is the bound.
    assert alone > 0.05, "the mesh is too quick to tell"
    assert ticks >= 5
