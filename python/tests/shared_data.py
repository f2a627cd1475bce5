"""Where the tests find data, by the rules of tests/common (shared_data_dir.cpp, test_data.h):
the shared real scans in ../shared/data beside the checkout, or $VDBMESH_DATA_DIR; a test
whose file is missing skips, unless VDBMESH_REQUIRE_DATA=1, when it fails. Small files
committed with the repository are in testdata/."""

import os
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[2]


def shared_data_dir():
    """The shared data folder, or None when it cannot be found."""
    env = os.environ.get("VDBMESH_DATA_DIR")
    if env:
        return Path(env) if Path(env).is_dir() else None
    for folder in [REPOSITORY, *REPOSITORY.parents]:
        candidate = folder.parent / "shared" / "data"
        if candidate.is_dir():
            return candidate
    return None


def data_required():
    """True when VDBMESH_REQUIRE_DATA=1: missing data is a failure, not a skip."""
    return os.environ.get("VDBMESH_REQUIRE_DATA") == "1"


def shared_data(relative):
    """The path of shared/data/<relative>; skips the test (fails it under
    VDBMESH_REQUIRE_DATA=1) when the file is missing."""
    folder = shared_data_dir()
    path = folder / relative if folder else None
    if path is None or not path.exists():
        message = f"shared data missing: {relative}"
        if data_required():
            pytest.fail(message + " (VDBMESH_REQUIRE_DATA=1)")
        pytest.skip(message)
    return path


def testdata(relative):
    """A file of the repository's testdata/ folder."""
    return REPOSITORY / "testdata" / relative


testdata.__test__ = False  # not a test, although pytest collects names starting with "test"
