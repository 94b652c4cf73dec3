"""Every command runs under every impact law or refuses from one place (pim.model.law)."""

from __future__ import annotations

import re
from pathlib import Path

import click
import pytest

import pim
from pim.model.case import LAWS
from pim.model.law import COMMAND_LAWS, command_law_refusal
from pim_cli.main import cli, main

ROOT = Path(__file__).resolve().parents[2]
FAST = {"solve", "draw", "fit"}         # the others run under every law in slow tests


def law_case(law: str, tmp_path, suffix: str = "") -> str:
    """ricsac9 under ``law`` (the bundled PC-Crash case for kudlich-slibar); ``suffix``
    "-reconstruct" for the inverse problem."""
    if law == "kudlich-slibar":
        return "ricsac9-pccrash" + suffix
    if law == "brach":
        return "ricsac9" + suffix
    text = (ROOT / f"pim/io/cases/ricsac9{suffix}.toml").read_text()
    path = tmp_path / "capped.toml"
    path.write_text(text.replace("[impact]\n", '[impact]\nlaw = "brach-capped"\n'
                                                'contact_friction = 0.9\n'))
    return str(path)


def arguments(command: str, case: str, tmp_path) -> list[str]:
    extra = {"draw": ["--out", str(tmp_path / "d.png")], "plot": ["--out", str(tmp_path / "p")],
             "baseline": ["--out", str(tmp_path / "b.json")],
             "compare": ["--out", str(tmp_path / "c"), "--no-animation", "--no-speed-error",
                         "--no-assumptions", "--no-progress"],
             "animate": ["--out", str(tmp_path / "a.mp4"), "--no-progress"],
             "reconstruct": ["--samples", "0"],
             "speed-error": ["--out", str(tmp_path / "s")],
             "assumptions": ["--out", str(tmp_path / "as")],
             "event": ["--out", str(tmp_path / "e"), "--no-progress", "--before", "0.2"]}
    return [command, case, *extra.get(command, [])]


def _params(command: str, law: str):
    marks = [] if command in FAST or law not in COMMAND_LAWS[command] else [pytest.mark.slow]
    return pytest.param(command, law, marks=marks, id=f"{command}-{law}")


@pytest.mark.parametrize("command,law", [_params(c, law) for c in COMMAND_LAWS for law in LAWS])
def test_each_command_runs_under_each_law_or_refuses_with_the_one_message(command, law,
                                                                          tmp_path, capsys):
    name = law_case(law, tmp_path, "-reconstruct" if command == "reconstruct" else "")
    code = main(arguments(command, name, tmp_path))
    err = capsys.readouterr().err
    refusal = command_law_refusal(command, pim.load_case(name))
    if law in COMMAND_LAWS[command]:
        assert refusal is None
        assert code == 0, err
        assert "cannot use impact law" not in err
    else:
        assert code == 2 and err.strip() == f"error: {refusal}", err
        assert f"pim {command} cannot use impact law {law!r}" in refusal
        assert pim.LAW_NAMES[law] in refusal and 'set impact.law = "brach"' in refusal


def test_every_command_that_takes_a_case_is_in_the_table():
    ctx = click.Context(cli)
    takes_case = {name for name in cli.list_commands(ctx)
                  if any(p.name in ("case_name", "case_names", "cases")
                         for p in cli.get_command(ctx, name).params)}
    assert takes_case == set(COMMAND_LAWS)


def test_commands_load_their_case_through_the_one_check():
    for path in (ROOT / "pim_cli").glob("*.py"):
        text = path.read_text()
        assert "require_brach" not in text, path
        calls = re.findall(r"\bload_case\(", text)
        assert path.name == "main.py" and len(calls) == 1 or not calls, path
