"""The animation: simulated vehicles solid, PIM's motion as a ghost that coincides with them
when the cross-check agrees, and visibly does not when it should not (issue 5)."""

import imageio.v3 as iio
import numpy as np
import pytest

import pim
from comparisons.animation.motion import analytic_motion
from comparisons.animation.collision import Framing, build_renderer
from comparisons.animation.render import COLORS, Renderer, write_animation
from pim_cli.main import main

CASE = pim.load_case("ricsac9")


@pytest.fixture(scope="module")
def renderer():
    return build_renderer(CASE, 0.355, 1.0, tyre=0.0)


def ghost_pixels(img):
    a = np.asarray(img).astype(int)
    return np.argwhere(np.abs(a - np.array(COLORS["ghost"])).sum(-1) == 0)


def distance_to_polygon_edges(points, poly):
    """Distance [px] of each (row, col) point to the closed polygon's edges (x, y)."""
    xy = points[:, ::-1].astype(float)
    best = np.full(len(xy), np.inf)
    for a, b in zip(poly, np.roll(poly, -1, axis=0), strict=True):
        d = b - a
        t = np.clip(((xy - a) @ d) / (d @ d), 0, 1)
        best = np.minimum(best, np.hypot(*(xy - (a + t[:, None] * d)).T))
    return best


def test_ghost_is_independent_free_motion_and_matches_the_simulation(renderer):
    # ghost: x(t) = x_C + V t, closed form from pim.solve; sim: pymunk's recorded trajectory
    result = pim.solve(CASE, 0.355, 1.0)
    t = renderer.times
    after = t > 0
    expected = np.asarray(CASE.vehicle1.cg) + t[after, None] * result.velocity1
    np.testing.assert_allclose(renderer.sim.vehicle1.position[after], expected, atol=1e-9)
    np.testing.assert_allclose(renderer.ghost.vehicle1.position[after], expected, atol=1e-12)
    assert renderer.ghost_offset_px() < 1e-6


def test_ghost_pixels_lie_on_the_simulated_outline_after_impact(renderer):
    frame = int(np.searchsorted(renderer.times, 1.0))
    pix = ghost_pixels(renderer.frame(frame))
    assert len(pix) > 50                    # the ghost is drawn
    on_sim = np.zeros(len(pix), bool)
    for vehicle in (1, 2):
        poly = renderer.outline_px(frame, vehicle)
        on_sim |= distance_to_polygon_edges(pix, poly) < 3.0
    # every ghost pixel not on an outline belongs to the ghost CG marks / velocity arrows,
    # which sit on the simulated CGs and arrows: most pixels are on the outline
    assert on_sim.mean() > 0.6


def test_a_wrong_answer_shows_as_an_offset_ghost():
    wrong = pim.solve(CASE, 0.355, 0.5)         # not what pymunk simulated (beta = 1)
    good = build_renderer(CASE, 0.355, 1.0, tyre=0.0)
    bad_ghost = analytic_motion(CASE, wrong, good.times)
    bad = Renderer(good.sim, bad_ghost)
    assert bad.ghost_offset_px() > 10
    frame = int(np.searchsorted(bad.times, 1.5))
    pix = ghost_pixels(bad.frame(frame))
    far = np.ones(len(pix), bool)
    for vehicle in (1, 2):
        far &= distance_to_polygon_edges(pix, bad.outline_px(frame, vehicle)) > 3.0
    assert far.sum() > 100                  # many ghost pixels away from the vehicles


def test_tyre_friction_ghost_uses_the_same_deceleration():
    r = build_renderer(CASE, 0.355, 1.0, tyre=0.7, after=3.0)
    # both decelerate (the ghost moves less than free motion) and stay within a pixel
    free = build_renderer(CASE, 0.355, 1.0, after=3.0, tyre=0.0)
    assert np.hypot(*(r.ghost.vehicle2.position[-1] - free.ghost.vehicle2.position[-1])) > 1.0
    assert r.ghost_offset_px() < 1.0


def test_frames_before_and_after_impact_differ_and_show_the_impulse(renderer):
    t = renderer.times
    i0 = int(np.argmin(np.abs(t)))
    red = np.array(COLORS["impulse"])
    def n_red(i):
        return int((np.abs(np.asarray(renderer.frame(i)).astype(int) - red).sum(-1) == 0).sum())
    assert n_red(i0) > 100                 # impulse arrow at the moment of impact
    assert n_red(len(t) - 1) == 0          # and gone later, with its label


def test_animate_command_writes_a_readable_mp4(tmp_path):
    out = tmp_path / "a.mp4"
    assert main(["animate", "hard-pole", "--out", str(out), "--before", "0.2", "--after",
                 "2", "--no-progress", "--gif", str(tmp_path / "a.gif")]) == 0
    frames = list(iio.imiter(out))
    assert len(frames) == 6 + 60 + 1
    assert max(frames[0].shape[:2]) <= 960 and frames[0].shape[2] == 3
    assert (tmp_path / "a.gif").stat().st_size > 1000


def test_a_failed_gif_leaves_no_mp4_either(tmp_path, capsys, monkeypatch):
    """A GIF that could not be written left the MP4 of the same run behind (the two files
    were renamed one after the other): now neither is written, exit 2, one line."""
    from PIL import Image

    def full_disk(self, *args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", full_disk)
    assert main(["animate", "hard-pole", "--out", str(tmp_path / "a.mp4"), "--after", "0.1",
                 "--no-progress", "--gif", str(tmp_path / "a.gif")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "No space left" in err, err
    assert list(tmp_path.iterdir()) == []


def test_render_rate_is_reported(tmp_path, renderer):
    info = write_animation(renderer, tmp_path / "x.mp4", progress=False)
    assert info.frames == len(renderer)
    assert info.render_fps == pytest.approx(info.frames / info.render_seconds)
    assert 0 < info.render_seconds < 60 and info.max_ghost_offset_px < 1e-6


def test_impulse_label_speaks_the_case_units_off_the_vehicles():
    """Issue 22: a US case's animation labelled its impulse in N s. Issue 33 item 7: the
    label ("1.117e+04 N s") covered a vehicle: it stands in the panel above the scene, in
    the reports' number format."""
    us = build_renderer(CASE, 0.355, 1.0, units="us", after=0.2)
    si = build_renderer(CASE, 0.355, 1.0, units="si", after=0.2)
    p = float(np.hypot(*pim.solve(CASE, 0.355, 1.0).impulse))
    i0 = int(np.searchsorted(us.times, 0.0))
    assert us.impulse_text(0.0).endswith(f"{p / (0.45359237 * 9.80665):.0f} lbf s")
    assert si.impulse_text(0.0).endswith(f"{p:.0f} N s")
    red = np.array(COLORS["impulse"])
    img = np.asarray(si.frame(i0)).astype(int)
    label = np.abs(img - red).sum(-1) < 90     # the text's anti-aliased pixels too
    arrow_only = label[si.TOP:]
    assert label[: si.TOP].sum() > 100         # the label's pixels are in the panel
    # in the scene the red pixels are the arrow: all within its box around C
    rows, cols = np.nonzero(arrow_only)
    c = si.to_px(CASE.impact.point)
    tip = c + si.sim.impacts[0].impulse * np.array([1, -1]) * si.impulse_scale
    lo, hi = np.minimum(c, tip) - 12, np.maximum(c, tip) + 12
    assert np.all((cols >= lo[0]) & (cols <= hi[0]))
    assert np.all((rows + si.TOP >= lo[1]) & (rows + si.TOP <= hi[1]))
@pytest.mark.parametrize("option, name", [("--out", "film.txt"), ("--gif", "small.png")])
def test_animate_to_a_wrong_suffix_is_one_line_and_exit_2(tmp_path, capsys, option, name):
    """Issue 22: `pim animate --out file.txt` gave a RuntimeError traceback from imageio."""
    args = ["animate", "hard-pole", "--no-progress", "--after", "0.1"]
    args += ["--out", str(tmp_path / "a.mp4")] if option == "--gif" else []
    assert main(args + [option, str(tmp_path / name)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"error: {option}") and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_a_failed_trailer_is_an_error_with_nothing_written(tmp_path, capsys, monkeypatch):
    """Issue 22: a full disk (ffmpeg's "Error writing trailer") gave exit 0 and a truncated
    MP4; the encoder's result is now checked: exit 2, one line, no file, no litter."""
    import os

    import imageio.v2

    real = imageio.v2.get_writer

    def truncating(path, *args, **kwargs):
        writer = real(path, *args, **kwargs)
        close = writer.close

        def close_and_cut():
            close()
            os.truncate(path, os.path.getsize(path) * 2 // 3)
        writer.close = close_and_cut
        return writer

    monkeypatch.setattr(imageio.v2, "get_writer", truncating)
    out = tmp_path / "a.mp4"
    assert main(["animate", "hard-pole", "--out", str(out), "--before", "0.1", "--after",
                 "0.3", "--no-progress"]) == 2
    err = capsys.readouterr().err.strip()
    assert "incomplete" in err and len(err.splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_the_framing_is_one_object_or_its_fields_by_name():
    """Issue 27 point 7: build_renderer takes a Framing, or its fields by name (overriding
    it); an unknown option is refused naming the allowed ones."""
    with pytest.raises(ValueError, match=r"unknown option\(s\) seconds; allowed: .*before, "
                                         r"after, fps, size"):
        build_renderer(CASE, 0.355, 1.0, seconds=2.0)
    r = build_renderer(CASE, 0.355, 1.0, framing=Framing(before=0.1, after=0.2, fps=10),
                       after=0.3, size=(320, 240))
    assert r.times[-1] == pytest.approx(0.3) and r.times[0] == pytest.approx(-0.1)
    assert len(r.times) == 5 and r.size == (320, 240)        # 10 frames per second
