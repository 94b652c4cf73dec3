"""Monte Carlo uncertainty (pim.uncertainty, pim.distributions) against closed forms.

Reference: a central, collinear impact (CGs and C on the x axis, n along x) has no rotation
and delta-V1 = (1 + eps) m2 / (m1 + m2) |v1x - v2x| (Brach & Brach 2011, ch. 6, the
collinear special case of the PIM equations), linear in each of v1x and eps separately.
"""

import json

import numpy as np
import pytest
from click.testing import CliRunner

import pim
from pim.analysis.montecarlo import first_order_indices
from pim.io.uncertainty_table import parse_uncertainty

M1, M2, V1, V2 = 1200.0, 1800.0, 15.0, -5.0


def collinear(table=None, eps=0.3):
    v1 = pim.Vehicle(M1, 2000.0, (-1.5, 0.0), (V1, 0.0), heading=0.0)
    v2 = pim.Vehicle(M2, 3500.0, (2.0, 0.0), (V2, 0.0), heading=np.pi)
    impact = pim.Impact((0.0, 0.0), np.pi, restitution=eps, beta=1.0)
    return pim.Case(v1, v2, impact, name="collinear",
                    uncertainty=None if table is None else parse_uncertainty(table))


def test_zero_spread_equals_the_deterministic_answer():
    case = pim.load_case("ricsac9")
    zero = parse_uncertainty({"vehicle1": {"mass": {"normal": "0 kg"},
                                           "velocity_x": {"plusminus": "0 ft/s"}},
                              "impact": {"restitution": {"uniform": [0.355, 0.355]},
                                         "normal_angle": {"normal": "0 deg"}}})
    result = pim.uncertainty(case, n=50, distributions=zero)
    ref = pim.solve(case, 0.355, 1.0)
    assert result.varying == ()
    expected = {"delta_v1_magnitude": ref.delta_v1_magnitude, "speed2": ref.speed2,
                "yaw_rate1": ref.yaw_rate1, "energy_loss": ref.energy_loss, "pdof2": ref.pdof2}
    for name, value in expected.items():
        s = result.stats[name]
        assert s.p5 == s.p50 == s.p95 == pytest.approx(float(value), rel=1e-12), name
        assert s.sd == pytest.approx(0.0, abs=1e-9 * abs(float(value)))


def test_linear_case_matches_analytic_percentiles():
    sd = 0.5
    case = collinear({"vehicle1": {"velocity_x": {"normal": f"{sd} m/s"}}}, eps=0.3)
    result = pim.uncertainty(case, n=200_000, seed=1)
    gain = 1.3 * M2 / (M1 + M2)
    mean, sigma = gain * (V1 - V2), gain * sd
    s = result.stats["delta_v1_magnitude"]
    assert s.mean == pytest.approx(mean, rel=2e-3)
    assert s.sd == pytest.approx(sigma, rel=1e-2)
    z95 = 1.6448536269514722
    assert s.p5 == pytest.approx(mean - z95 * sigma, abs=0.02 * sigma)
    assert s.p50 == pytest.approx(mean, abs=0.02 * sigma)
    assert s.p95 == pytest.approx(mean + z95 * sigma, abs=0.02 * sigma)
    # binning error: the tail bins of a normal input are wide (a few 1e-3 at B = 100)
    assert result.sensitivity["delta_v1_magnitude"][0] == ("vehicle1.velocity_x",
                                                          pytest.approx(1, abs=5e-3))


def test_two_inputs_analytic_variance_and_first_order_indices():
    """Y = c (1 + eps) w, eps ~ U(0.1, 0.5), w = v1x - v2x ~ N(20, 1.5): independent inputs."""
    lo, hi, sd = 0.1, 0.5, 1.5
    case = collinear({"vehicle1": {"velocity_x": {"normal": f"{sd} m/s"}},
                      "impact": {"restitution": {"uniform": [lo, hi]}}})
    result = pim.uncertainty(case, n=400_000, seed=2)
    c, w = M2 / (M1 + M2), V1 - V2
    e_mean, e_var = 1 + (lo + hi) / 2, (hi - lo) ** 2 / 12
    var = c**2 * ((e_var + e_mean**2) * (sd**2 + w**2) - (e_mean * w) ** 2)
    assert result.stats["delta_v1_magnitude"].sd ** 2 == pytest.approx(var, rel=1.5e-2)
    indices = dict(result.sensitivity["delta_v1_magnitude"])
    assert indices["impact.restitution"] == pytest.approx(c**2 * w**2 * e_var / var, abs=0.01)
    assert indices["vehicle1.velocity_x"] == pytest.approx(c**2 * e_mean**2 * sd**2 / var,
                                                           abs=0.01)


def test_first_order_indices_of_an_additive_function():
    """Y = X1 + 2 X2 + 0 X3 with X ~ U(0, 1): S = (1/5, 4/5, 0)."""
    rng = np.random.default_rng(3)
    u = {f"x{i}": rng.random(200_000) for i in (1, 2, 3)}
    idx = dict(first_order_indices(u["x1"] + 2 * u["x2"], u))
    assert idx["x1"] == pytest.approx(0.2, abs=5e-3)
    assert idx["x2"] == pytest.approx(0.8, abs=5e-3)
    assert idx["x3"] == pytest.approx(0.0, abs=2e-3)






def test_case_file_table_and_command(tmp_path):
    text = (pim.io.casefile.resources.files("pim.io") / "cases" / "ricsac9.toml").read_text()
    text = text.split("[uncertainty]")[0]        # replace the bundled table by this one
    text += ('\n[uncertainty]\nvehicle1.mass = {normal = "20 kg"}\n'
             'impact.normal_angle = {uniform = ["-5 deg", "5 deg"]}\n'
             'impact.restitution = {uniform = [0.2, 0.5]}\n')
    path = tmp_path / "case.toml"
    path.write_text(text)
    case = pim.load_case(path)
    assert set(case.uncertainty.inputs) == {"vehicle1.mass", "impact.normal_angle",
                                            "impact.restitution"}
    from pim_cli.main import cli

    png = tmp_path / "hist.png"
    out = CliRunner().invoke(cli, ["uncertainty", str(path), "--samples", "20000", "--json",
                                   "--png", str(png)])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    rows = {r["output"]: r for r in data["outputs"]}
    dv1 = rows["delta_v1_magnitude"]
    assert dv1["p5"] < dv1["p50"] < dv1["p95"]
    assert rows["delta_v1_magnitude"]["sensitivity"][0]["input"] == "impact.restitution"
    assert png.stat().st_size > 10_000
    assert not list(tmp_path.glob(".*tmp"))


def test_ricsac9_ships_an_uncertainty_table(capsys):
    # issue 12 item 2: `pim uncertainty ricsac9` works out of the box, in the file's units
    from pim_cli.main import main

    assert main(["uncertainty", "ricsac9", "--samples", "2000"]) == 0
    out = capsys.readouterr().out
    assert "mph" in out and "deg/s" in out and "2,000 samples" in out and "ft/s" not in out


def test_barrier_has_no_pdof_in_the_uncertainty_table(tmp_path, capsys):
    from pim_cli.main import main

    text = (pim.io.casefile.resources.files("pim.io") / "cases"
            / "hard-barrier.toml").read_text()
    path = tmp_path / "barrier.toml"
    path.write_text(text + '\n[uncertainty]\nimpact.normal_angle = {plusminus = "5 deg"}\n')
    assert main(["uncertainty", str(path), "--samples", "2000"]) == 0
    out = capsys.readouterr().out
    assert "PDOF of vehicle 1" in out and "PDOF of vehicle 2" not in out


def test_chunked_run_equals_the_in_memory_run_of_the_same_samples():
    """One varying input: chunks of rng.random draw the same stream as one call, so the
    chunked run sees exactly the in-memory run's samples (issue 22 item 4: exact
    percentiles on bounded memory)."""
    case = collinear({"vehicle1": {"velocity_x": {"normal": "0.5 m/s"}}})
    whole = pim.uncertainty(case, n=30_000, seed=4)
    done = []
    chunked = pim.uncertainty(case, n=30_000, seed=4, chunk_size=4_000, progress=done.append)
    assert sum(done) == 30_000 and len(done) == 8
    for name in ("delta_v1_magnitude", "speed2", "energy_loss"):
        a, b = whole.stats[name], chunked.stats[name]
        assert (b.p5, b.p50, b.p95) == (a.p5, a.p50, a.p95), name
        assert b.mean == pytest.approx(a.mean, rel=1e-12)
        assert b.sd == pytest.approx(a.sd, rel=1e-9)
    # the first chunk's samples are kept for histograms, not all of them
    assert chunked.samples["speed1"].size == 4_000
    assert whole.samples["speed1"].size == 30_000


def test_chunked_statistics_agree_within_their_sampling_error():
    """Several inputs: the chunked samples differ from the one-call samples; the percentiles
    agree within 4 standard errors of a quantile, sqrt(p (1 - p) / n) / f(x_p) (f the density;
    normal outputs: f(x_p) = phi(z_p) / sd), combined for two independent runs."""
    lo, hi, sd = 0.1, 0.5, 1.5
    case = collinear({"vehicle1": {"velocity_x": {"normal": f"{sd} m/s"}},
                      "impact": {"restitution": {"uniform": [lo, hi]}}})
    n = 40_000
    a = pim.uncertainty(case, n=n, seed=7)
    b = pim.uncertainty(case, n=n, seed=7, chunk_size=3_000)
    sa, sb = a.stats["delta_v1_magnitude"], b.stats["delta_v1_magnitude"]
    phi95, phi50 = 0.10313564037537128, 0.3989422804014327     # phi(1.645), phi(0)
    for p, phi, x, y in ((0.05, phi95, sa.p5, sb.p5), (0.5, phi50, sa.p50, sb.p50),
                         (0.95, phi95, sa.p95, sb.p95)):
        se = np.sqrt(p * (1 - p) / n) * sa.sd / phi
        assert abs(x - y) < 4 * np.sqrt(2) * se, p
    assert abs(sa.mean - sb.mean) < 4 * np.sqrt(2 / n) * sa.sd
    ia, ib = (dict(r.sensitivity["delta_v1_magnitude"]) for r in (a, b))
    for name in ia:     # indices: standard error about 1 / sqrt(n) = 0.005 here
        assert ib[name] == pytest.approx(ia[name], abs=0.03), name


def test_samples_in_exponent_form_and_the_memory_check(monkeypatch):
    from pim.analysis import montecarlo
    from pim_cli.main import main

    assert main(["uncertainty", "ricsac9", "--samples", "2e3", "--no-progress"]) == 0
    assert main(["uncertainty", "ricsac9", "--samples", "2.5e0"]) == 2
    assert main(["uncertainty", "ricsac9", "--samples", "1.5e3x"]) == 2
    monkeypatch.setattr(montecarlo, "available_memory", lambda: 10 * 2**20)
    assert main(["uncertainty", "ricsac9", "--samples", "1e8"]) == 2


def test_memory_estimate_is_bounded_in_the_sample_count():
    from pim.analysis.montecarlo import CHUNK_SIZE, memory_estimate

    assert memory_estimate(1e5) < memory_estimate(CHUNK_SIZE)
    # above a chunk only the kept percentile windows grow: 1e8 samples stay under 4 GB
    assert memory_estimate(1e8) < 2 * 2**30


def test_memory_shortfall_says_what_is_needed_and_available():
    from pim.analysis.montecarlo import memory_estimate, memory_shortfall

    need = memory_estimate(10**8)
    assert memory_shortfall(10**8, available=need) is None
    text = memory_shortfall(10**8, available=2**28)
    assert text == f"needs about {need / 2**30:.1f} GiB of memory and 0.2 GiB are available"
