"""Shared fixtures of the Python tests: where the source and build trees are, and small logs."""
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("LEGKIT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
BUILD = pathlib.Path(os.environ.get("LEGKIT_BUILD_DIR", SOURCE / "build"))
ICUB_LOG = SOURCE / "data" / "icub-walking" / "walking.csv"
ICUB_CONFIG = SOURCE / "config" / "robots" / "icub.yaml"
LEGKIT = BUILD / "legkit"


@pytest.fixture(scope="session")
def trot_log():
    """Three seconds of the analytic trot, seed 1 (0.01 s to simulate)."""
    import legkit

    return legkit.sim.simulate("trot", duration=3.0, seed=1)
