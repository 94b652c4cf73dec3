"""docs/regression.md's examples run as written in a project of one's own: the workflow's
commands, the pytest plugin's test file and the drift shown after a case changed, in a
temporary project that is then moved (issue 28: baselines stored absolute case paths, so a
moved or cloned project failed with "neither a file nor a bundled case")."""

import os
import re
import shutil
import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
DOC = (ROOT / "docs" / "regression.md").read_text()


def block(kind: str, after: str) -> str:
    """The first fenced ``kind`` block of the document after the text ``after``."""
    start = DOC.index(after)
    match = re.compile(rf"```{kind}\n(.*?)```", re.S).search(DOC, start)
    return match.group(1)


@pytest.fixture(scope="module")
def shell(tmp_path_factory):
    """Runs a command line as a user types it: ``pim`` is this checkout's command line."""
    folder = tmp_path_factory.mktemp("bin")
    (folder / "pim").write_text(f'#!/bin/sh\nexec "{sys.executable}" -m pim_cli "$@"\n')
    (folder / "pim").chmod(0o755)
    env = {**os.environ, "PATH": f"{folder}{os.pathsep}{os.environ['PATH']}",
           "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}

    def run(command: str, cwd: Path) -> subprocess.CompletedProcess:
        return subprocess.run(["bash", "-c", command], cwd=cwd, env=env, capture_output=True,
                              text=True, timeout=600)
    return run


def pytest_in(shell, cwd: Path, target: str) -> subprocess.CompletedProcess:
    return shell(f'"{sys.executable}" -m pytest -q -p no:cacheprovider -p no:randomly '
                 f"{target}", cwd)


def columns(line: str) -> list[str]:
    return line.split()


@pytest.mark.slow   # 20-25 s of subprocesses; the default suite keeps test_baseline's
# relative-path and moved-project tests (the CI budget: pytest -m slow runs this)
def test_the_documented_workflow_survives_a_move(tmp_path, shell):
    project = tmp_path / "project"
    (project / "cases").mkdir(parents=True)
    shutil.copy(resources.files("pim.io") / "cases" / "ricsac9.toml",
                project / "cases" / "my-case.toml")            # "here a copy of RICSAC 9"
    for line in block("bash", "## The workflow").strip().splitlines():
        done = shell(line, project)
        assert done.returncode == 0, (line, done.stdout, done.stderr)
    assert "all 262 quantities within tolerance" in done.stdout
    (project / "test_my_cases.py").write_text(block("python", "## In your own test suite"))

    moved = tmp_path / "elsewhere" / "project-moved"          # a clone somewhere else
    moved.parent.mkdir()
    shutil.move(project, moved)
    done = shell("pim check baselines/mine.json", moved)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout == "baselines/mine.json: all 262 quantities within tolerance\n"
    done = pytest_in(shell, moved.parent, "project-moved/test_my_cases.py")   # another cwd
    assert "2 passed" in done.stdout, done.stdout + done.stderr

    case = moved / "cases" / "my-case.toml"
    case.write_text(case.read_text().replace('weight = "4896.2 lbf"', 'weight = "5000 lbf"'))
    done = shell("pim check baselines/mine.json", moved)
    assert done.returncode == 1, done.stdout + done.stderr
    shown = block("text", "Change a case").strip().splitlines()
    assert shown[0] == "$ pim check baselines/mine.json"
    printed = done.stdout.splitlines()
    assert printed[:3] == shown[1:4]            # input changed, summary, header
    rows = {tuple(columns(line)[:2]): columns(line) for line in printed[3:]}
    for line in shown[4:-1]:                    # the rows shown, then "..."
        doc, now = columns(line), rows[tuple(columns(line)[:2])]
        assert [float(x) for x in now[2:5]] == pytest.approx([float(x) for x in doc[2:5]],
                                                             rel=1e-9)
        assert 1 / 3 < float(now[5]) / float(doc[5]) < 3      # a tolerance from round-off
        assert now[6:] == doc[6:]
    assert shown[-1] == "..."
    done = pytest_in(shell, moved, "test_my_cases.py")
    assert "1 failed, 1 passed" in done.stdout and "solve.velocity1_x" in done.stdout, \
        done.stdout
