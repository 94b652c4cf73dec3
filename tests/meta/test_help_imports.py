"""``pim --help`` imports no command module and nothing heavy (issue 27 point 8).

The list of commands is printed from the command line's own table (pim_cli/commands.py):
listing them must not load a command's module, the model (numpy, pim), the simulator
(sim, pymunk), scipy, matplotlib, numba or the comparisons. Before the table, `pim --help`
loaded every command through its entry point and, with them, all of these (1.8 s). Checked
in a fresh interpreter through the console script's own entry (``pim_cli.run``); how fast
it answers is printed by benchmarks/bench_help.py.
"""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: Top-level packages `pim --help` must not import.
HEAVY = ("numpy", "scipy", "pymunk", "matplotlib", "numba", "pint", "imageio", "pim", "sim",
         "comparisons")
#: The only modules of the command line it may import: the console script, the group and
#: the table.
ALLOWED = {"pim_cli", "pim_cli.main", "pim_cli.commands"}


def modules_loaded_by(args: list[str]) -> tuple[int, str, set[str]]:
    """Run ``pim ARGS`` as the console script does in a fresh interpreter; its exit code,
    stdout and the names in sys.modules when it ended."""
    code = textwrap.dedent(f"""
        import atexit, sys
        def loaded():
            print(" ".join(sorted(sys.modules)), file=sys.stderr)
        atexit.register(loaded)
        sys.argv = ["pim", *{args!r}]
        from pim_cli import run
        run()
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT)
    return out.returncode, out.stdout, set(out.stderr.split())


@pytest.mark.parametrize("args", [["--help"], [], ["-h"]])
def test_the_help_imports_no_command_module_and_nothing_heavy(args):
    code, stdout, modules = modules_loaded_by(args)
    heavy = sorted(m for m in modules if m.split(".")[0] in HEAVY)
    commands = sorted(m for m in modules if m.split(".")[0] == "pim_cli")
    assert set(commands) <= ALLOWED, commands
    assert heavy == [], heavy
    assert code == 0 and "Reconstruct a crash:" in stdout, (code, stdout)


def test_the_check_sees_a_command_module_loaded():
    """The check can fail: a command's own help loads its module (and the model)."""
    code, stdout, modules = modules_loaded_by(["fit", "--help"])
    assert code == 0 and "Usage: pim fit" in stdout
    assert "pim_cli.fit" in modules and "numpy" in modules
