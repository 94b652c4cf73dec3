"""The command table (pim_cli/commands.py) and ``pim --help`` (issue 27 point 8).

``pim --help`` lists every command under its group from the table alone, each summary a
whole sentence that is the first sentence of its command's docstring; that it imports no
command module is tests/meta/test_help_imports.py's (how fast it answers is printed by
benchmarks/bench_help.py, not timed here).
"""

import importlib
import re

import click
import pytest

from pim_cli.commands import COMMANDS, GROUPS, LOOK_ALIKES, by_name
from pim_cli.main import cli, main

#: How a summary starts: with what the command does (an imperative verb).
VERBS = {"List", "Solve", "Fit", "Reconstruct", "Propagate", "Rank", "Write", "Draw",
         "Animate", "Validate", "Compare", "Test", "Simulate", "Sweep", "Run", "Record",
         "Rerun"}


def first_sentence(doc: str) -> str:
    """The first sentence of a docstring's first paragraph, whitespace collapsed: up to the
    first period followed by a space (or the paragraph's end) outside brackets, so that
    "(e.g. x)" does not end it."""
    paragraph = " ".join(doc.strip().split("\n\n")[0].split())
    depth = 0
    for i, ch in enumerate(paragraph):
        depth += (ch in "([{") - (ch in ")]}")
        if ch == "." and depth == 0 and paragraph[i + 1:i + 2] in ("", " "):
            return paragraph[:i + 1]
    return paragraph


def sentence_problems(text: str) -> list[str]:
    """Why ``text`` is not one whole sentence saying what a command does (empty: it is)."""
    problems = []
    if text.split(" ")[0] not in VERBS:
        problems.append(f"does not start with a verb of {sorted(VERBS)}")
    if not text.endswith(".") or "..." in text:
        problems.append("does not end with one period")
    depth = 0
    for ch in text:
        depth += (ch in "([{") - (ch in ")]}")
        if depth < 0:
            break
    if depth:
        problems.append("has unbalanced brackets")
    if first_sentence(text) != text:
        problems.append("is more than one sentence")
    return problems


def command_of(row):
    module, _, function = row.target.partition(":")
    return getattr(importlib.import_module(module), function)


def help_text(capsys) -> str:
    assert main(["--help"]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("row", COMMANDS, ids=[c.name for c in COMMANDS])
def test_each_row_names_its_click_command(row):
    command = command_of(row)
    assert isinstance(command, click.Command) and command.name == row.name
    assert cli.get_command(click.Context(cli), row.name) is command
    assert by_name(row.name) is row


@pytest.mark.parametrize("row", COMMANDS, ids=[c.name for c in COMMANDS])
def test_each_summary_is_a_whole_sentence_and_its_docstrings_first(row):
    assert sentence_problems(row.summary) == [], row.summary
    assert first_sentence(command_of(row).help) == row.summary


@pytest.mark.parametrize("summary, problem", [
    ("Reconstruct CASE's unknowns (e.g.", "unbalanced brackets"),
    ("Record every output CASE...", "one period"),
    ("Monte Carlo of CASE's [uncertainty] table.", "verb"),
    ("Solve CASE. Print the table.", "more than one sentence"),
    ("Solve CASE and print", "one period")])
def test_a_cut_or_verbless_summary_is_caught(summary, problem):
    """The summaries `pim --help` printed before (cut by click at 45 characters, or no
    sentence at all) fail the check."""
    assert any(problem in p for p in sentence_problems(summary)), summary


def test_the_first_sentence_skips_periods_inside_brackets():
    assert first_sentence("Reconstruct x (e.g. the speeds) from y.\n\nMore.") == \
        "Reconstruct x (e.g. the speeds) from y."
    assert first_sentence("Rerun a baseline's\n    cases. Then list.") == \
        "Rerun a baseline's cases."


def test_help_lists_every_command_once_under_its_group_with_its_whole_summary(capsys):
    text = help_text(capsys)
    headings = [line[:-1] for line in text.splitlines() if line.endswith(":")
                and not line.startswith(" ")]
    assert headings == ["Options", *GROUPS, "Which command to use"]
    sections = re.split(r"^(?=\S.*:$)", text, flags=re.M)
    for group in GROUPS:
        body = next(s for s in sections if s.startswith(group + ":"))
        names = [line.split()[0] for line in body.splitlines()[1:]
                 if line.startswith("  ") and not line.startswith("   ")]
        assert names == [c.name for c in COMMANDS if c.group == group], group
        flat = " ".join(body.split()).replace("- ", "-")   # click wraps after a hyphen
        for c in COMMANDS:
            if c.group == group:
                assert f"{c.name} {c.summary}".replace("- ", "-") in flat, c.name
    assert len({c.name for c in COMMANDS}) == len(COMMANDS)
    assert {c.group for c in COMMANDS} == set(GROUPS)


def test_help_says_which_of_the_look_alikes_to_use(capsys):
    flat = " ".join(help_text(capsys).split())
    assert "Which command to use:" in flat
    for names, choice in LOOK_ALIKES:
        assert f"{names} {choice}" in flat
    named = {"solve", "sim", "compare", "fit", "reconstruct", "uncertainty", "sensitivity",
             "validate", "validate-models", "check", "draw", "plot"}
    listed = {w.strip("?,") for names, _ in LOOK_ALIKES for w in names.split()
              if not w.startswith("--") and w != "or"}
    assert listed == named and all(by_name(n) for n in listed)
    options = {p.opts[0] for p in command_of(by_name("reconstruct")).params}
    assert "--samples" in options


def test_pim_alone_prints_the_help(capsys):
    """click 8.2 turned it into an error ("error: Usage: ...", exit 2)."""
    assert main([]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("Usage: pim") and "Reconstruct a crash:" in captured.out
    assert captured.err == ""


def test_a_commands_help_loads_it(capsys):
    assert main(["reconstruct", "--help"]) == 0
    assert "Reconstruct CASE's unknowns, such as the impact speeds" in capsys.readouterr().out


def test_an_unknown_command_is_one_line_and_exit_2(capsys):
    assert main(["slove", "ricsac9"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "slove" in err and len(err.strip().splitlines()) == 1
