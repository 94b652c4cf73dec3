"""The command line only parses, dispatches and prints (issue 27): three rules on the source
of every module of pim_cli/.

1. **No arithmetic.** No ``*``, ``/``, ``//``, ``%``, ``**`` or ``@`` (nor their augmented
   assignments ``*=`` ...), except ``/`` joining a path: ``Path(...) / x`` or
   ``folder / "name"`` (a string or f-string on the right). Unit conversion of results,
   shares, scales, time budgets and counts are done by the layers that own them
   (pim.analysis, pim.io.units, comparisons/report) and the command line prints what they
   return.
2. **No unit conversion and no numpy.** No pim_cli module imports ``convert`` from
   ``pim.io.units`` (values reach the user's units in the presenters of comparisons/report
   or the typed results; the command line only chooses the units: ``display_units``,
   ``messages_in``, ``parse`` for its options) nor numpy.
3. **Short helpers.** No function other than a click command is over :data:`LIMIT` lines
   (``def`` to its last line, as tests/meta/test_function_length.py counts): a helper that
   grows past it is building text or rows, which belongs to a presenter.

Before the move (main at 1217882) all three failed: rule 1 in pim_cli/fit.py (fit_json's
scaling, _print_fit's residual table), reconstruct.py (the Monte Carlo budget, the stage
count), uncertainty.py (the memory check, the share of inadmissible samples) and compare.py
(the speed-error lines' ms); rule 2 in fit.py, main.py, reconstruct.py and uncertainty.py;
rule 3 in fit.py (_print_fit 45 lines, _print_sensitivity 39), reconstruct.py (_reconstruct
50) and compare.py (_speed_error_case 39).
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: Longest helper (not a click command) of the command line [lines].
LIMIT = 32
_ARITHMETIC = (ast.Mult, ast.Div, ast.FloorDiv, ast.Mod, ast.Pow, ast.MatMult)


def _path_join(node: ast.BinOp) -> bool:
    """``Path(...) / x`` or ``x / "name"`` / ``x / f"..."``: a path, not a number."""
    left, right = node.left, node.right
    return isinstance(node.op, ast.Div) and (
        (isinstance(left, ast.Call) and isinstance(left.func, ast.Name)
         and left.func.id == "Path")
        or isinstance(right, ast.JoinedStr)
        or (isinstance(right, ast.Constant) and isinstance(right.value, str)))


def arithmetic(source: str) -> list[tuple[int, str]]:
    """(line, expression) of each arithmetic operation in ``source`` (rule 1)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.BinOp) and isinstance(node.op, _ARITHMETIC) \
                and not _path_join(node):
            found.append((node.lineno, ast.unparse(node)))
        elif isinstance(node, ast.AugAssign) and isinstance(node.op, _ARITHMETIC):
            found.append((node.lineno, ast.unparse(node)))
    return found


def conversions(source: str) -> list[tuple[int, str]]:
    """(line, statement) of each import of ``pim.io.units.convert`` or of numpy, and each
    use of a name ``np`` (rule 2)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module == "pim.io.units" and any(
                alias.name == "convert" for alias in node.names):
            found.append((node.lineno, ast.unparse(node)))
        elif isinstance(node, ast.Import | ast.ImportFrom) and any(
                (getattr(node, "module", None) or alias.name).split(".")[0] == "numpy"
                for alias in node.names):
            found.append((node.lineno, ast.unparse(node)))
        elif isinstance(node, ast.Name) and node.id == "np":
            found.append((node.lineno, "np"))
    return found


def _is_command(node: ast.FunctionDef) -> bool:
    """Decorated by ``click.command(...)`` / ``click.group(...)``."""
    for deco in node.decorator_list:
        target = deco.func if isinstance(deco, ast.Call) else deco
        if isinstance(target, ast.Attribute) and target.attr in ("command", "group"):
            return True
    return False


def long_helpers(source: str) -> list[tuple[str, int]]:
    """(name, lines) of each function in ``source`` over :data:`LIMIT` lines that is not a
    click command (rule 3)."""
    return [(node.name, node.end_lineno - node.lineno + 1)
            for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
            and not _is_command(node) and node.end_lineno - node.lineno + 1 > LIMIT]


def _sources():
    for path in sorted((ROOT / "pim_cli").rglob("*.py")):
        yield path.relative_to(ROOT).as_posix(), path.read_text()


def test_the_command_line_does_no_arithmetic():
    found = [f"{name}:{line}: {text}" for name, source in _sources()
             for line, text in arithmetic(source)]
    assert not found, "arithmetic in the command line (move it to its layer):\n" + \
        "\n".join(found)


def test_the_command_line_converts_no_units_and_uses_no_numpy():
    found = [f"{name}:{line}: {text}" for name, source in _sources()
             for line, text in conversions(source)]
    assert not found, "unit conversion or numpy in the command line:\n" + "\n".join(found)


def test_the_command_lines_helpers_are_short():
    found = [f"{name}: {function} has {lines} lines (limit {LIMIT})"
             for name, source in _sources() for function, lines in long_helpers(source)]
    assert not found, "\n".join(found)


PLANTED = '''
import click
import numpy as np
from pim.io.units import convert, display_units


def shown(value, units):
    factor, unit = convert(1.0, "velocity", units)
    return value * factor, unit


def share(bad, n):
    x = 1
    x *= 100 * bad / n
    return np.round(x)


def paths(folder, name):
    return Path("out") / (name or "case"), folder / "report.html", folder / f"{name}.md"


@click.command()
def command():
''' + "    click.echo('line')\n" * (LIMIT + 5) + '''

def helper():
''' + "    click.echo('line')\n" * LIMIT


def test_the_rules_catch_a_planted_breach():
    assert sorted(line for line, _ in arithmetic(PLANTED)) == [9, 14, 14, 14]
    assert [text for _, text in conversions(PLANTED)] == [
        "import numpy as np", "from pim.io.units import convert, display_units", "np"]
    assert long_helpers(PLANTED) == [("helper", LIMIT + 1)]     # the command is exempt
