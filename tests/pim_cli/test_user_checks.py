"""Issue 28, item 1: no impossible answer leaves with exit 0 unnoticed, and the geometry is
checked, on the command line.

The cases are the issue's, on an SI case as a new user writes it
(tests/data/suv-into-sedan-si.toml): C 47 m from both cars, a CG written in mm, a heading of
270 deg for a car driving north, a T-bone whose outlines run into each other after the
impact, a negative beta. Each test failed on the code before (exit 0, or no message).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pim_cli.main import main

SUV = (Path(__file__).parents[1] / "data" / "suv-into-sedan-si.toml").read_text()
FAR = SUV.replace('point = ["0 m", "0 m"]', 'point = ["46.3 m", "8.2 m"]')   # 47 m away


def write(tmp_path, text, name="case.toml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def run(args, capsys):
    try:
        code = main(args)
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_c_47_m_away_exits_1_with_the_reasons_before_the_table(tmp_path):
    """Before: "warning: the normal impulse is not positive", the table, exit 0."""
    path = write(tmp_path, FAR)
    run_ = subprocess.run([sys.executable, "-m", "pim_cli", "solve", path],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          check=False, env={**os.environ, "PYTHONUNBUFFERED": "1"})
    assert run_.returncode == 1, run_.stdout
    lines = run_.stdout.splitlines()
    table = next(i for i, line in enumerate(lines) if line.startswith("quantity"))
    reasons = [i for i, line in enumerate(lines) if line.startswith("error: ")]
    before = [lines[i] for i in reasons if i < table]
    assert len(before) == 3 and all(i < table for i in reasons[:3])
    assert before[0].startswith("error: vehicle1: C is 46.58 m from its CG, farther than its "
                                "whole length (4.6 m)")
    assert before[1].startswith("error: vehicle2: C is 47.45 m from its CG")
    assert before[2].startswith("error: inadmissible answer: the normal impulse is not positive "
                                "(the contact would pull) (Pn = -")
    assert before[2].endswith(" N s)")
    assert lines[-1] == ("error: the answer is inadmissible (3 reasons above); "
                         "--allow-inadmissible accepts it")
    assert "Traceback" not in run_.stdout


def test_allow_inadmissible_prints_the_reasons_as_warnings_and_exits_0(tmp_path, capsys):
    code, out, err = run(["solve", write(tmp_path, FAR), "--allow-inadmissible"], capsys)
    assert code == 0 and "quantity" in out and "error" not in err
    lines = err.splitlines()
    assert [line.split(": ")[1] for line in lines[:3]] == ["vehicle1", "vehicle2",
                                                           "inadmissible answer"]
    assert all(line.startswith("warning: ") for line in lines)


def test_json_says_admissible_false_with_the_reasons_and_exits_1(tmp_path, capsys):
    code, out, err = run(["solve", write(tmp_path, FAR), "--json"], capsys)
    data = json.loads(out)
    assert code == 1
    assert data["admissible"] is False and len(data["inadmissible"]) == 3
    assert data["inadmissible"][2].startswith("inadmissible answer: the normal impulse")
    assert data["problems"][:3] == data["inadmissible"]
    assert err.count("error: ") == 4        # the three reasons and the closing line


def test_an_admissible_answer_of_an_impossible_scene_still_exits_1(tmp_path, capsys):
    """C 47 m north (0, 47 m): the contact pushes (Pn > 0), but neither car reaches C."""
    text = SUV.replace('point = ["0 m", "0 m"]', 'point = ["0 m", "47 m"]')
    code, out, err = run(["solve", write(tmp_path, text), "--json"], capsys)
    data = json.loads(out)
    assert code == 1 and data["admissible"] is False
    assert not any("inadmissible answer" in text for text in data["inadmissible"])
    assert all("farther than its whole length" in text for text in data["inadmissible"])


def test_cg_in_mm_warns_with_the_numbers_and_exits_0(tmp_path, capsys):
    """Before: no warning; only the SUV's delta-V moved (6.34 -> 6.51 m/s here)."""
    text = SUV.replace('cg = ["0 m", "-2.2 m"]', 'cg = ["0 mm", "-2.2 mm"]')
    code, out, err = run(["solve", write(tmp_path, text)], capsys)
    assert code == 0
    assert ("warning: vehicle2: C is 0.0022 m from its CG, less than 0.05 x its length "
            "(4.8 m)") in err
    assert "mm or cm instead of m" in err


def test_heading_270_for_a_car_driving_north_warns_reversing(tmp_path, capsys):
    """Before: no warning, and PDOF 168 deg (a rear impact) printed as if meant."""
    text = SUV.replace('heading = "90 deg"', 'heading = "270 deg"')
    code, out, err = run(["solve", write(tmp_path, text)], capsys)
    assert code == 0 and "warning: vehicle2 is reversing" in err
    assert "reversing = true in [vehicle2]" in err
    stated = text.replace('mass = "2100 kg"', 'mass = "2100 kg"\nreversing = true')
    code, out, err = run(["solve", write(tmp_path, stated, "stated.toml")], capsys)
    assert code == 0 and err == ""


@pytest.mark.parametrize("command", [["solve", "ricsac9"], ["sim", "ricsac9"],
                                     ["fit", "ricsac9"], ["sensitivity", "ricsac9"],
                                     ["uncertainty", "ricsac9"], ["draw", "ricsac9"]])
def test_negative_beta_is_refused_with_the_range(capsys, command):
    """Before: "warning: beta < 0: the tangential impulse drives the sliding", exit 0."""
    code, out, err = run([*command, "--beta", "-0.2"], capsys)
    assert code == 2 and out == ""
    assert err.startswith("error: Invalid value for '--beta': '-0.2': beta (fraction of mu0) "
                          "must be a finite number >= 0: Brach's law takes beta in [0, 1]")
    assert err.count("\n") == 1


def test_negative_beta_in_the_case_file_names_the_field(tmp_path, capsys):
    code, out, err = run(["solve", write(tmp_path, SUV.replace("beta = 1", "beta = -0.3"))],
                         capsys)
    assert code == 2 and err.startswith("error: impact.beta (fraction of mu0) must be")
    text = SUV + '\n[uncertainty]\nimpact.beta = {uniform = [-0.1, 0.5]}\n'
    code, out, err = run(["uncertainty", write(tmp_path, text, "mc.toml")], capsys)
    assert code == 2 and "uncertainty.impact.beta: value -0.1 outside the admissible range" \
        in err


def test_beta_above_one_exits_1_unless_allowed(capsys):
    code, out, err = run(["solve", "ricsac9", "--beta", "1.2"], capsys)
    assert code == 1 and "quantity" in out
    assert "error: inadmissible answer: |mu| > |mu0| (beta > 1)" in err
    assert "(beta = 1.2, mu = 0.6148, mu0 = 0.5123; Brach's law takes beta in [0, 1])" in err
    assert "lbf s" in err                       # RICSAC 9 is written in ft and lbf
    assert run(["solve", "ricsac9", "--beta", "1.2", "--allow-inadmissible"], capsys)[0] == 0
    code, out, err = run(["sensitivity", "ricsac9", "--eps", "0.3", "--beta", "1.2"], capsys)
    assert code == 1 and "|mu| > |mu0|" in err and "per sigma" in out


def test_fit_beyond_beta_one_exits_1(capsys):
    """docs/fit.md: with --beta-range 0 3 the optimum moves to beta ~ 1.4, outside Brach's
    law: said first, exit 1 (before: warnings and exit 0)."""
    code, out, err = run(["fit", "ricsac9", "--beta-range", "0", "3", "--json"], capsys)
    data = json.loads(out)
    assert code == 1 and data["admissible"] is False and data["beta"] > 1.3
    assert any("beta > 1" in text for text in data["inadmissible"])
    code, out, err = run(["fit", "ricsac9", "--beta-range", "-0.5", "1"], capsys)
    assert code == 2 and "0 <= beta_min" in err


def test_monte_carlo_says_the_share_of_inadmissible_samples(tmp_path, capsys):
    """A beta normal about 0.95 (sd 0.1) exceeds 1 with probability 1 - Phi(0.5) = 0.3085
    (the truncation at 0 removes 1e-21): those samples are left out, and the output says how
    many and why before the table (4 binomial sd: 0.041)."""
    text = SUV + '\n[uncertainty]\nimpact.beta = {normal = 0.1}\n'
    text = text.replace("beta = 1\n", "beta = 0.95\n", 1)
    code, out, err = run(["uncertainty", write(tmp_path, text), "-n", "2000", "--json"], capsys)
    data = json.loads(out)
    bad = data["samples_inadmissible"]
    assert code == 0 and data["admissible"] is True and abs(bad / 2000 - 0.3085) < 0.041
    assert data["samples_admissible"] + bad == 2000
    assert data["inadmissible_samples"] == "left out of the percentiles and indices"
    note = next(line for line in err.splitlines() if line.startswith("note: "))
    assert note.startswith(f"note: {bad:,} of 2,000 samples ({100 * bad / 2000:.3g} %) are "
                           f"inadmissible impacts, left out of the percentiles")
    assert "warning: samples: |mu| > |mu0| (beta > 1)" in err


def test_baseline_refuses_an_inadmissible_case(tmp_path, capsys):
    out_file = tmp_path / "b.json"
    code, out, err = run(["baseline", write(tmp_path, FAR), "--out", str(out_file)], capsys)
    assert code == 1 and not out_file.exists()
    assert "case.toml: inadmissible answer: the normal impulse is not positive" in err
    code, out, err = run(["baseline", write(tmp_path, FAR), "--out", str(out_file),
                          "--allow-inadmissible", "--without", "uncertainty"], capsys)
    assert code == 0 and out_file.exists()


TBONE = SUV.replace('cg = ["0 m", "-2.2 m"]', 'cg = ["0.8 m", "-2.2 m"]')   # C at its front left


def test_t_bone_secondary_contact_is_a_note_with_time_and_place(tmp_path, capsys):
    """The SUV strikes the sedan's right side with C 0.8 m left of its centre line: it yaws
    and its front runs into the sedan again about 0.1 s after the impact (the rigid scene
    plays on through it). Before: `pim sim` said nothing."""
    path = write(tmp_path, TBONE)
    code, out, err = run(["sim", path], capsys)
    note = [line for line in err.splitlines() if line.startswith("note: secondary impact")]
    assert code == 0 and len(note) == 1
    assert "at t = 0.10" in note[0] and "after the impact at (x, y) = (" in note[0]
    assert " m, " in note[0] and "vehicle 1's right side against vehicle 2's front" in note[0]
    code, out, err = run(["sim", path, "--json", "--units", "us"], capsys)
    contact = json.loads(out)["secondary_impact"]
    assert code == 0 and 0.09 < contact["time"] < 0.11 and contact["length_unit"] == "ft"
    assert contact["parts"] == ["right side", "front"]


def test_t_bone_animation_notes_the_secondary_contact_on_stderr(tmp_path, capsys):
    """Before: one line on stdout, after the file name, without the place. The single
    impact's animation (--single-impact) still notes the contact it leaves unsolved; the
    whole event (the default since issue 32) solves it as a second impact."""
    out_file = tmp_path / "tbone.mp4"
    code, out, err = run(["animate", write(tmp_path, TBONE), "--out", str(out_file),
                          "--after", "0.5", "--fps", "10", "--size", "320", "240",
                          "--no-progress", "--single-impact", "--tyre-friction", "0"], capsys)
    assert code == 0 and out_file.exists()
    assert "secondary" not in out
    assert "note: secondary impact at t = 0.10" in err and "(x, y) = (" in err
    code, out, err = run(["animate", write(tmp_path, TBONE), "--out", str(out_file),
                          "--after", "0.5", "--fps", "10", "--size", "320", "240",
                          "--no-progress", "--json"], capsys)
    assert code == 0 and "secondary impact" not in err
    assert json.loads(out)["whole_event"] and json.loads(out)["impacts"] >= 2


def test_reconstruction_notes_run_outs_that_run_into_each_other():
    """pim reconstruct animates both fitted run-outs from the impact to rest: when they meet
    again the command says when and where, and that the run-out model leaves that second
    impact out. Here the sedan slides east and the SUV backs away, y(t) = -2.2 - 1.5 t +
    1.5 t^2 m, then comes back: its front (y + 2.4 m) passes the sedan's right side (y = 0)
    again when t^2 - t + 2/15 = 0, t = 0.8416 s: the first frame after it is 0.85 s."""
    from types import SimpleNamespace

    import numpy as np

    from comparisons.report.reconstruct import runout_contact
    from pim.analysis.reconstruction import PostImpact
    from pim.io.casefile import parse_case
    from pim.model.runout import Runout

    case = parse_case(__import__("tomllib").loads(SUV))
    t = np.linspace(0.0, 2.0, 41)
    sedan = np.c_[0.3 + 2 * np.minimum(t, 1.0), np.full_like(t, 0.9), np.zeros_like(t)]
    suv = np.c_[np.zeros_like(t), -2.2 - 1.5 * t + 1.5 * t**2, np.full_like(t, np.pi / 2)]

    def fit(states):
        full = np.c_[states, np.zeros((len(t), 3))]      # velocities unused by the check
        run = Runout(t, full, full[-1, :2], float(full[-1, 2]), float(t[-1]), True)
        return SimpleNamespace(runout=run, stopped=True)

    post = PostImpact(case, {1: fit(sedan), 2: fit(suv)}, {}, {}, None, [])
    rec = SimpleNamespace(case=case, post=post)
    contact = runout_contact(rec, "us")
    assert contact["time"] == pytest.approx(0.85) and contact["length_unit"] == "ft"
    assert contact["message"].startswith("secondary impact at t = 0.85 s after the impact at "
                                         "(x, y) = (")
    assert "the two fitted run-outs run into each other again" in contact["message"]
    rec.post.runouts.pop(2)
    assert runout_contact(rec, "us") is None
