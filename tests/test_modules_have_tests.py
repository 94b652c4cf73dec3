"""Every module of pim/ has its own test file, tests/test_<module>.py (pvlib's layout).

Where two modules share a stem, or a command-line module is exercised through its
command, the test file is named here.
"""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: pim module -> its test file, where the stem alone does not name it.
EXCEPTIONS = {
    "pim/cli/main.py": "test_cli.py",
    "pim/cli/fit.py": "test_fitting.py",            # pim fit / sensitivity / plot commands
    "pim/cli/uncertainty.py": "test_montecarlo.py",  # pim uncertainty
}
MODULES = sorted(str(p.relative_to(ROOT)) for p in (ROOT / "pim").rglob("*.py")
                 if p.name != "__init__.py")


@pytest.mark.parametrize("module", MODULES)
def test_module_has_its_own_test_file(module):
    name = EXCEPTIONS.get(module, f"test_{Path(module).stem}.py")
    assert (ROOT / "tests" / name).exists(), f"{module}: no tests/{name}"
