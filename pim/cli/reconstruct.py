"""``pim reconstruct CASE --out DIR``: evidence -> post-impact motion -> impact speeds.

Today's chain: the run-out inverse of each vehicle with ``[evidence]`` gives its post-impact
motion (with standard deviations from the evidence's sigmas through the fit's Jacobian);
the pre-impact speeds along the case's directions come from linear momentum with their
propagated standard deviations (5/50/95 % of the normal approximation). The inverse PIM
(``pim.fit`` with ``free=`` the ``[unknown]`` table) joins when pim.fit gains ``free``
(issue 13a). Writes DIR/report.md, DIR/reconstruction.csv and DIR/scene.png.
"""

from __future__ import annotations

import click

from .main import case_argument, echo_json, json_option, units_option

__all__ = ["reconstruct"]

Z95 = 1.6448536269514722  # standard normal 95 % quantile


@click.command()
@case_argument
@click.option("--out", "out", type=click.Path(file_okay=False), default=None,
              help="Directory for report.md, reconstruction.csv and scene.png.")
@units_option
@json_option
def reconstruct(case_name, out, units, as_json):
    """Reconstruct CASE's pre-impact speeds from its [evidence] (rest positions, wheels)."""
    from pathlib import Path

    import numpy as np

    from ..analysis.reconstruction import post_impact_motion
    from ..io.casefile import load_case
    from ..io.files import save_figure, write_text
    from ..io.units import convert

    case = load_case(case_name)
    units = units or case.units
    post = post_impact_motion(case)
    rows = []  # (dotted name, kind, value, sigma) in SI
    for i, fit in post.runouts.items():
        cov = post.velocity_sigma[i]
        rows += [(f"post_impact.vehicle{i}.velocity_x", "velocity", fit.velocity[0],
                  float(np.sqrt(cov[0, 0]))),
                 (f"post_impact.vehicle{i}.velocity_y", "velocity", fit.velocity[1],
                  float(np.sqrt(cov[1, 1]))),
                 (f"post_impact.vehicle{i}.yaw_rate", "angular_velocity", fit.yaw_rate,
                  post.yaw_rate_sigma[i])]
    if post.momentum is not None:
        m = post.momentum
        rows += [("vehicle1.speed", "velocity", m.speed1, m.sigma1),
                 ("vehicle2.speed", "velocity", m.speed2, m.sigma2)]
    table = [{"name": name, "kind": kind, "value": float(value),
              "p5": float(value - Z95 * sigma), "p50": float(value),
              "p95": float(value + Z95 * sigma)} for name, kind, value, sigma in rows]
    if as_json:
        echo_json({"case": case.name, "units": "si", "messages": post.messages,
                   "unknowns": {r["name"]: {k: r[k] for k in ("value", "p5", "p50", "p95")}
                                for r in table}})
    lines, csv = [], ["name,unit,value,p5,p50,p95"]
    for r in table:
        values, unit = convert([r["value"], r["p5"], r["p50"], r["p95"]], r["kind"], units)
        csv.append(f"{r['name']},{unit}," + ",".join(f"{v:.6g}" for v in values))
        lines.append(f"| {r['name']} | {values[0]:.4g} | {values[1]:.4g} | {values[2]:.4g} "
                     f"| {values[3]:.4g} | {unit} |")
    if not as_json:
        for line in lines:
            click.echo(line)
        for message in post.messages:
            click.echo(f"warning: {message}")
    if out:
        from ..plotting.reconstruction_scene import reconstruction_figure

        directory = Path(out)
        directory.mkdir(parents=True, exist_ok=True)
        report = [f"# Reconstruction of {case.name}", "",
                  "Post-impact motion from the run-out inverse of each vehicle's rest "
                  "evidence; pre-impact speeds from linear momentum (5/50/95 % of the "
                  "normal approximation propagated from the evidence's sigmas).", "",
                  "| quantity | value | 5 % | 50 % | 95 % | unit |",
                  "|---|---|---|---|---|---|", *lines, ""]
        report += [f"- warning: {m}" for m in post.messages] or ["No warnings."]
        report += ["", "![scene](scene.png)", ""]
        write_text(directory / "report.md", "\n".join(report))
        write_text(directory / "reconstruction.csv", "\n".join(csv) + "\n")
        save_figure(reconstruction_figure(post, units), directory / "scene.png")
