"""Shared helpers: the repository's root and the command line built by `scripts/build`."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The debug build's folder (the binary, the example plugins): `scripts/test` says where, as the
# build may live outside the checkout (CARGO_TARGET_DIR).
BUILD = pathlib.Path(os.environ.get("SUBTGRAPH_BUILD_DIR") or ROOT / "target" / "debug")


@pytest.fixture(scope="session")
def cli():
    """Runs the `subtgraph` binary that `scripts/test` builds (`BUILD/subtgraph`, or
    $SUBTGRAPH_BIN), returning the finished process."""
    binary = os.environ.get("SUBTGRAPH_BIN") or str(BUILD / "subtgraph")
    if not os.path.exists(binary):
        pytest.skip(f"{binary} is missing: build it with `scripts/build` (scripts/test does)")

    def run(*args, check=True):
        return subprocess.run(
            [binary, *map(str, args)], capture_output=True, text=True, check=check
        )

    return run


@pytest.fixture(autouse=True)
def _forget_python_components():
    """Each test registers its own Python components; none leaks into the next."""
    import subtgraph

    yield
    for c in subtgraph.components():
        if c["origin"] == "python":
            subtgraph.unregister(c["name"])
