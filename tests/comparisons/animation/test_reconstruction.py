"""comparisons/animation/reconstruction.py: the reconstruction's video drawn by the one
renderer: the frames run from the impact pose to the fitted rest (against the run-outs they
come from), the measured rest positions are drawn, the MP4 reads back."""

import numpy as np
import pytest

import pim
from comparisons.animation.reconstruction import (
    reconstruction_event,
    reconstruction_renderer,
    write_reconstruction_video,
)
from comparisons.animation.render import COLORS
from pim.analysis.reconstruction import PostImpact
from pim.analysis.runout_fit import RunoutFit
from pim.model.runout import runout

TRUTH = pim.solve(pim.load_case("ricsac9"), 0.355, 1.0)


@pytest.fixture(scope="module")
def post():
    """The synthetic case's post-impact motion, run forward from the known truth (what the
    run-out inverse gives back, without its 20 s of fitting)."""
    case = pim.load_case("synthetic-runout")
    fits = {}
    for i in (1, 2):
        v, ev = getattr(case, f"vehicle{i}"), getattr(case.evidence, f"vehicle{i}")
        vel, w = getattr(TRUTH, f"velocity{i}"), float(getattr(TRUTH, f"yaw_rate{i}"))
        run = runout(ev.runout_vehicle(float(v.mass), float(v.yaw_inertia)), v.cg,
                     float(v.heading), vel, w)
        fits[i] = RunoutFit(vel, w, float(np.hypot(*vel)), float(np.arctan2(vel[1], vel[0])),
                            run, run.rest_position, run.rest_heading, (), np.zeros(0), 0.0,
                            np.zeros((3, 3)), True, True, (), [], "")
    return PostImpact(case, fits, {}, {}, None, [])


def test_frames_run_from_the_impact_pose_to_rest(post):
    event = reconstruction_event(post, TRUTH, fps=20, hold=0.5)
    longest = max(f.runout.time[-1] for f in post.runouts.values())
    assert event.time[0] == 0.0 and event.time[-1] >= longest + 0.5 - 0.05
    for i, fit in post.runouts.items():
        vehicle, track = getattr(post.case, f"vehicle{i}"), event.tracks[i - 1]
        np.testing.assert_allclose(track.position[0], vehicle.cg, atol=1e-12)
        assert track.heading[0] == pytest.approx(float(vehicle.heading))
        np.testing.assert_allclose(track.position[-1], fit.rest_position, atol=1e-12)
        assert track.heading[-1] == pytest.approx(fit.rest_heading)
        assert track.wheels is not None          # the evidence's axles, for tyre marks
    assert event.phase[-1] == "rest" and len(event.impacts) == 1


def test_measured_rest_positions_are_drawn(post):
    r = reconstruction_renderer(post, TRUTH, fps=5, size=(480, 400))
    img = np.asarray(r.frame(0)).astype(int)
    black = (np.abs(img - np.array(COLORS["rest"])).sum(-1) == 0)[r.TOP:]
    assert black.sum() > 40                          # the dotted outlines
    ev = post.case.evidence.vehicle1
    c = r.to_px(ev.rest_position) - np.array([0, r.TOP])
    rows, cols = np.nonzero(black)
    assert np.min(np.hypot(cols - c[0], rows - c[1])) < 3.5 * r.scale   # around its rest CG


def test_the_mp4_has_every_frame(post, tmp_path):
    import imageio.v3 as iio

    info = write_reconstruction_video(post, TRUTH, tmp_path / "crash.mp4", units="us", fps=10,
                                      size=(320, 240), progress=False)
    frames = iio.imread(info.path)
    assert frames.shape[0] == len(reconstruction_event(post, TRUTH, 10).time)
    assert frames.shape[1:] == (240, 320, 3)
    assert not list(tmp_path.glob(".*tmp*"))          # atomic: no temporary file left


@pytest.mark.parametrize("kwargs, words", [({"fps": 0}, "fps"), ({"fps": 2.5}, "fps"),
                                           ({"hold": -1.0}, "hold")])
def test_bad_settings_are_named(post, kwargs, words):
    with pytest.raises(ValueError, match=words):
        reconstruction_event(post, TRUTH, **kwargs)


def test_the_plan_view_draws_the_fitted_paths_in_the_chosen_units(post):
    from comparisons.animation.reconstruction import reconstruction_plan

    fig_si = reconstruction_plan(post, TRUTH, "si")
    fig_us = reconstruction_plan(post, TRUTH, "us")
    line_si = fig_si.axes[0].lines[0].get_xydata()
    line_us = fig_us.axes[0].lines[0].get_xydata()
    np.testing.assert_allclose(line_si[-1], post.runouts[1].rest_position, atol=1e-9)
    np.testing.assert_allclose(line_us, line_si / 0.3048)
    assert fig_us.axes[0].get_xlabel() == "x [ft]"
    assert "outlines every" in fig_si.axes[0].get_title()


def test_the_run_outs_lay_tyre_marks(post):
    # the fitted run-outs slide after the impact (RICSAC 9's separation speeds, locked
    # wheels) and stop: their tracks carry sliding flags, the video and plan view draw marks
    event = reconstruction_event(post, TRUTH, fps=10, hold=0.5)
    for track in event.tracks:
        assert track.sliding is not None and track.sliding[1].all()   # sliding just after
        assert not track.sliding[-1].any()                              # not at rest
    r = reconstruction_renderer(post, TRUTH, fps=10, size=(480, 400))
    last = np.asarray(r.frame(len(event) - 1)).astype(int)
    marks = (np.abs(last - np.array(COLORS["marks"])).sum(-1) == 0)[r.TOP:]
    assert marks.sum() > 200                        # each wheel's mark, a few px wide
    first = np.asarray(r.frame(0)).astype(int)
    assert (np.abs(first - np.array(COLORS["marks"])).sum(-1) == 0)[r.TOP:].sum() == 0
    from comparisons.animation.reconstruction import reconstruction_plan
    from comparisons.animation.render import COLORS as C

    grey = tuple(c / 255 for c in C["marks"])
    lines = [ln for ln in reconstruction_plan(post, TRUTH).axes[0].lines
             if ln.get_color() == grey]
    assert len(lines) == 8                          # four wheels of each vehicle
    assert all(np.isfinite(ln.get_xydata()).all(axis=1).sum() > 5 for ln in lines)


def test_a_motion_fitted_through_the_event_is_animated_through_its_further_impacts():
    """Rest positions reached through a side slap: the reconstruction fits the post-impact
    motion through the event, and its animation (and plan view) shows that event: its
    further impacts marked, no outline entering the other once they came apart, the
    vehicles ending where the evidence rests them (the animation showed the single-impact
    run-outs, with the first impact only). The run-outs' secondary contact note ("not
    reliable") is not given: the fit solved that contact."""
    from comparisons.docs.event import side_slap_case, with_rest_evidence
    from comparisons.report.reconstruct import runout_contact
    from pim.analysis.reconstruction import post_impact_motion, reconstruct

    case = with_rest_evidence(side_slap_case())
    rec = reconstruct(case, unknown={"vehicle1.speed": (0.0, 40.0),
                                     "vehicle2.speed": (0.0, 40.0)}, samples=0)
    post = rec.post
    assert post.event_fit is not None and post.event_fit.impacts >= 1
    event = reconstruction_event(post, rec.fit.result, fps=25, hold=0.5)
    assert len(event.impacts) == 1 + post.event_fit.impacts
    assert event.impacts[0].time == 0.0 and event.impacts[1].time > 0.0
    assert any(str(p).startswith("impact 2") for p in event.phase)
    for i, track in enumerate(event.tracks, start=1):
        rest = getattr(case.evidence, f"vehicle{i}").rest_position
        assert np.hypot(*(track.position[-1] - rest)) < 0.05, i
    assert _deepest_corner(event.at(np.arange(0.005, event.time[-1], 0.002))) < 0.05
    single = post_impact_motion(case, through_event=False)
    assert single.event_fit is None and single.event().impacts == ()
    assert runout_contact(rec, "si") is None


def _deepest_corner(event) -> float:
    """How deep [m] any outline corner goes into the other outline once the two have come
    apart after the impact (its crush overlap), over the event's samples (convex outlines:
    a corner's depth is its least distance inside the other's edges)."""
    corners = [t.placed(t.outline) for t in event.tracks]
    depth = np.full(len(event.time), -np.inf)
    for a, b in ((0, 1), (1, 0)):
        edge = np.roll(corners[b], -1, axis=1) - corners[b]                   # (N, K, 2)
        normal = np.stack([edge[..., 1], -edge[..., 0]], -1)
        normal /= np.hypot(normal[..., 0], normal[..., 1])[..., None]
        inward = -np.sign(np.einsum("nkj,nkj->nk", normal, corners[b].mean(1, keepdims=True)
                                    - corners[b]))[..., None] * normal       # (N, K, 2)
        rel = corners[a][:, :, None, :] - corners[b][:, None, :, :]            # (N, P, K, 2)
        inside = np.einsum("npkj,nkj->npk", rel, -inward).min(-1)             # (N, P)
        depth = np.maximum(depth, inside.max(-1))
    apart = np.flatnonzero(depth <= 0.0)
    assert len(apart), "the outlines never come apart"
    return float(depth[apart[0]:].max())
