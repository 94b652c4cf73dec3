"""Test configuration: hypothesis runs derandomized on CI and without its example database
(a local database replays examples an earlier run found, which a clean CI clone never sees),
so a red CI is reproducible;
no test writes into the checkout (:func:`checkout_stays_clean`, every run);
fixtures shared by several test files (a file may define its own of the same name)."""

import os
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import settings

import pim
from tests.checkout import gained, listing

ROOT = Path(__file__).resolve().parents[1]

settings.register_profile("ci", derandomize=True, database=None, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")


@pytest.fixture(scope="session", autouse=True)
def checkout_stays_clean():
    """Fail the run when the checkout gains a file or folder while it runs (a test wrote
    outside its temporary folder: ``out/`` from a command run without ``--out`` among
    them); each xdist worker checks from its first test to its last."""
    before = listing(ROOT)
    yield
    new = gained(before, listing(ROOT))
    if new:
        pytest.fail(f"the test run wrote into the checkout {ROOT}: {', '.join(new[:10])}"
                    f"{' ...' if len(new) > 10 else ''} (write into tmp_path, or give "
                    f"the command --out)", pytrace=False)


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
