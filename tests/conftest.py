"""Test configuration: hypothesis runs derandomized on CI and without its example database
(a local database replays examples an earlier run found, which a clean CI clone never sees),
so a red CI is reproducible;
fixtures shared by several test files (a file may define its own of the same name)."""

import os
from dataclasses import replace

import pytest
from hypothesis import settings

import pim

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


@pytest.fixture(scope="session")
def ricsac9():
    """RICSAC collision 9 as bundled (Brach Fig. 7.14)."""
    return pim.load_case("ricsac9")


@pytest.fixture(scope="session")
def spinning(ricsac9):
    """RICSAC 9 rotated and moved, with pre-impact yaw rates on both vehicles."""
    case = ricsac9.transformed(rotation=-1.1, translation=(5.0, 1.0))
    return replace(case, vehicle1=replace(case.vehicle1, yaw_rate=0.6),
                   vehicle2=replace(case.vehicle2, yaw_rate=-0.3))
