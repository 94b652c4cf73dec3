"""pim/plotting/reconstruction_animation.py: frame states against the run-outs they come from
(first frame = impact pose, last = rest), and the MP4 read back."""

import numpy as np
import pytest

import pim
from pim.analysis.reconstruction import PostImpact
from pim.analysis.runout_fit import RunoutFit
from pim.model.runout import runout
from pim.plotting.reconstruction_animation import frame_states, write_reconstruction_mp4


@pytest.fixture(scope="module")
def post():
    """The synthetic case's post-impact motion, run forward from the known truth (what the
    run-out inverse gives back, without its 20 s of fitting)."""
    case = pim.load_case("synthetic-runout")
    truth = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)
    fits = {}
    for i in (1, 2):
        v, ev = getattr(case, f"vehicle{i}"), getattr(case.evidence, f"vehicle{i}")
        vel, w = getattr(truth, f"velocity{i}"), float(getattr(truth, f"yaw_rate{i}"))
        run = runout(ev.runout_vehicle(float(v.mass), float(v.yaw_inertia)), v.cg,
                     float(v.heading), vel, w)
        fits[i] = RunoutFit(vel, w, float(np.hypot(*vel)), float(np.arctan2(vel[1], vel[0])),
                            run, run.rest_position, run.rest_heading, (), np.zeros(0), 0.0,
                            np.zeros((3, 3)), True, True, (), [], "")
    return PostImpact(case, fits, {}, {}, None, [])


def test_frames_run_from_the_impact_pose_to_rest(post):
    frames = frame_states(post, fps=20, hold=0.5)
    longest = max(f.runout.time[-1] for f in post.runouts.values())
    assert frames.times[0] == 0.0 and frames.times[-1] >= longest + 0.5 - 0.05
    for i, fit in post.runouts.items():
        vehicle = getattr(post.case, f"vehicle{i}")
        np.testing.assert_allclose(frames.states[i][0, :2], vehicle.cg, atol=1e-12)
        assert frames.states[i][0, 2] == pytest.approx(float(vehicle.heading))
        np.testing.assert_allclose(frames.states[i][-1, :2], fit.rest_position, atol=1e-12)
        assert frames.states[i][-1, 2] == pytest.approx(fit.rest_heading)


def test_the_mp4_has_every_frame(post, tmp_path):
    import imageio.v3 as iio

    path = write_reconstruction_mp4(post, tmp_path / "crash.mp4", units="us", fps=10,
                                    hold=0.2, size=(4, 3), dpi=60)
    frames = iio.imread(path)
    assert frames.shape[0] == len(frame_states(post, 10, 0.2).times)
    assert frames.shape[1:] == (180, 240, 3)
    assert not list(tmp_path.glob(".*tmp*"))          # atomic: no temporary file left


@pytest.mark.parametrize("kwargs, words", [({"fps": 0}, "fps"), ({"fps": 2.5}, "fps"),
                                           ({"hold": -1.0}, "hold")])
def test_bad_settings_are_named(post, kwargs, words):
    with pytest.raises(ValueError, match=words):
        frame_states(post, **kwargs)
