"""Scene figure of a reconstruction (pim.plotting.reconstruction_scene)."""

from dataclasses import replace

import numpy as np

import pim
from pim.analysis.reconstruction import PostImpact
from pim.analysis.runout_fit import RunoutFit
from pim.model.evidence import Evidence, VehicleEvidence
from pim.model.runout import runout
from pim.plotting.reconstruction_scene import reconstruction_figure


def test_figure_draws_paths_in_the_chosen_units():
    case = pim.load_case("ricsac9")
    ev = VehicleEvidence(np.array([3.0, 4.0]), 1.0, 2.6, 1.5, 1.2, 0.7)
    run = runout(ev.runout_vehicle(1000.0, 1500.0), case.vehicle1.cg, 0.0, [5.0, 3.0], 1.0)
    fit = RunoutFit(np.array([5.0, 3.0]), 1.0, np.hypot(5, 3), np.arctan2(3, 5), run,
                    run.rest_position, run.rest_heading, (), np.zeros(3), 0.0,
                    np.eye(3), True, True, (), [], "")
    post = PostImpact(replace(case, evidence=Evidence(ev)), {1: fit}, {1: np.eye(2)},
                      {1: 0.1}, None, [])
    fig_si = reconstruction_figure(post, "si")
    fig_us = reconstruction_figure(post, "us")
    line_si = fig_si.axes[0].lines[0].get_xydata()
    line_us = fig_us.axes[0].lines[0].get_xydata()
    np.testing.assert_allclose(line_si, run.states[:, :2])
    np.testing.assert_allclose(line_us, run.states[:, :2] / 0.3048)
    assert fig_us.axes[0].get_xlabel() == "x [ft]"
