"""Ctrl-C interrupts a long call: the library checks for signals as it goes, while the GIL is
released, and leaves no output behind."""

import os
import signal
import threading

import numpy as np
import pytest

import vdbmesh


@pytest.fixture(scope="module")
def noise():
    # Every cell straddles the level: the whole volume is active band. Measured on the 2-core
    # development machine: converting it takes about 0.7 s, meshing it over 10 s, far longer
    # than the 0.1 s before the signal.
    return np.random.default_rng(1).random((288, 288, 288), dtype=np.float32)


@pytest.fixture(autouse=True)
def python_handles_sigint():
    # A process started in the background by a non-interactive shell inherits SIGINT ignored,
    # and Python then installs no handler of its own: give it back for these tests.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def _interrupt_after(seconds):
    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals reach the main thread")
def test_ctrl_c_interrupts_a_conversion_and_writes_nothing(tmp_path, noise):
    output = tmp_path / "noise.vdb"
    timer = _interrupt_after(0.1)
    try:
        with pytest.raises(KeyboardInterrupt):
            vdbmesh.to_vdb(noise, 0.5, output)
    finally:
        timer.join()
    # Without the check the call would run to its end, write the file, and only then let
    # Python raise KeyboardInterrupt.
    assert not output.exists()
    assert list(tmp_path.iterdir()) == []  # no temporary left either


@pytest.mark.skipif(threading.current_thread() is not threading.main_thread(), reason="signals reach the main thread")
def test_ctrl_c_interrupts_mesh(noise):
    timer = _interrupt_after(0.1)
    meshes = []
    try:
        with pytest.raises(KeyboardInterrupt):
            meshes.append(vdbmesh.mesh(noise, 0.5, method="mc"))
    finally:
        timer.join()
    assert not meshes
