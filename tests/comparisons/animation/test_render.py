"""The one renderer on events built by hand (no simulation: fast): tyre marks where a wheel
slides and nowhere else, the frame fitted to the motion, the clock above the scene (not under
a video player's controls), speeds in the user's unit, every impact marked, the measured rest
drawn (issue 32 item 4); an interrupt reaches the MP4 writer between frames (issue 33)."""

import os
import signal
from dataclasses import replace

import numpy as np
import pytest

from comparisons.animation.render import COLORS, Look, Renderer, write_animation
from pim.model.event import Event, ImpactRecord, Track, phase_labels

OUTLINE = np.array([[2.0, 0.9], [-2.5, 0.9], [-2.5, -0.9], [2.0, -0.9]])


def slide(n=31, slide_from=15):
    """Vehicle 1 runs along +x at 10 m/s, slides from sample ``slide_from`` (t = 1.5 s,
    sliding flags set there) to rest at 2.5 s; vehicle 2 stands 6 m to its left; an impact
    at t = 0.5 s."""
    t = np.linspace(0.0, 3.0, n)
    s = np.clip(t - 1.5, 0.0, 1.0)
    x = 10 * np.minimum(t, 1.5) + 10 * s - 5 * s ** 2
    v = np.where(t < 1.5, 10.0, 10 - 10 * s)
    sliding = np.zeros((n, 4), bool)
    sliding[slide_from:] = True
    one = Track(np.column_stack([x, np.zeros(n)]), np.zeros(n),
                np.column_stack([v, np.zeros(n)]), np.zeros(n), sliding=sliding,
                outline=OUTLINE)
    two = Track(np.tile([15.0, 6.0], (n, 1)), np.full(n, np.pi / 2), np.zeros((n, 2)),
                np.zeros(n), outline=OUTLINE)
    impact = ImpactRecord(0.5, np.array([5.0, 3.0]), 0.3, "brach", {"eps": 0.1, "beta": 1.0},
                          np.array([1000.0, 0.0]), np.zeros((2, 2)), np.zeros((2, 2)),
                          np.zeros(2), np.zeros(2), 10.0, np.zeros(2))
    return Event(t, one, two, phase_labels(t, [0.5], 2.9), impacts=(impact,))


def near(img, color, tol=0):
    return np.abs(np.asarray(img).astype(int) - np.array(color)).sum(-1) <= tol


def test_tyre_marks_where_the_wheels_slide_and_nowhere_else():
    ev = slide()
    r = Renderer(ev, look=Look(size=(640, 360)))
    marks = near(r.frame(len(ev) - 1), COLORS["marks"])
    marks[: r.TOP] = False                  # the panel's anti-aliased text
    assert marks.sum() > 100
    rows, cols = np.nonzero(marks)
    start = r.to_px([ev.vehicle1.position[15, 0] + OUTLINE[:, 0].min(), 0])[0]
    assert cols.min() >= start - 3          # none behind the rear wheels where it slid first
    early = Renderer(ev, look=Look(size=(640, 360)))
    assert near(early.frame(10), COLORS["marks"])[r.TOP:].sum() == 0    # not yet sliding
    rolling = replace(ev.vehicle1, sliding=np.zeros((len(ev), 4), bool))
    unsliding = Renderer(replace(ev, vehicle1=rolling), look=Look(size=(640, 360)))
    assert near(unsliding.frame(len(ev) - 1), COLORS["marks"])[r.TOP:].sum() == 0


def test_the_frame_is_fitted_to_the_motion():
    """The outlines over the whole event fill the scene area both ways (the size taken from
    the motion's aspect); the old fixed 4:3 frame left a long slide in a strip."""
    r = Renderer(slide())
    pts = np.concatenate([r.outline_px(k, v) for k in range(len(r)) for v in (1, 2)])
    left, top, right, bottom = r.scene_box()
    fill_w = np.ptp(pts[:, 0]) / (right - left)
    fill_h = np.ptp(pts[:, 1]) / (bottom - top)
    assert max(fill_w, fill_h) >= 0.9
    assert r.size[1] < 720 and r.size[0] == 960      # a wide, low frame for a long slide
    assert min(pts[:, 0]) >= 0 and max(pts[:, 0]) <= r.size[0] and min(pts[:, 1]) >= top


def test_the_clock_is_above_the_scene_not_under_the_video_controls():
    """Two frames at rest differ only in the clock: every differing pixel is in the panel
    at the top (a video player's controls cover the bottom 40 px or so)."""
    ev = slide()
    r = Renderer(ev, look=Look(size=(640, 480)))
    a = np.asarray(r.frame(len(ev) - 2)).astype(int)
    b = np.asarray(r.frame(len(ev) - 1)).astype(int)
    rows = np.nonzero(np.abs(a - b).sum(-1).sum(1))[0]
    assert len(rows) and rows.max() < r.TOP and rows.max() < 0.25 * r.size[1]


def test_speeds_and_phase_in_the_users_units():
    ev = slide()
    si = Renderer(ev, look=Look(units="si", size=(640, 360)))
    us = Renderer(ev, look=Look(units="us", size=(640, 360)))
    k = 5
    v = ev.vehicle1.speed[k]
    assert f"vehicle 1: {v * 3.6:.3g} km/h" in si.status(k)
    assert f"vehicle 1: {v / 0.44704:.3g} mph" in us.status(k)
    assert si.phase(0) == "approach" or si.phase(0).startswith("after") is False
    assert si.phase(len(ev) - 1) == "at rest"
    assert "after impact 1" in si.status(10)


def test_each_impact_is_marked_at_its_c():
    ev = slide()
    r = Renderer(ev, look=Look(size=(640, 360)))
    green = near(r.frame(0), COLORS["contact"])
    c = r.to_px(ev.impacts[0].point)
    rows, cols = np.nonzero(green[r.TOP:])
    assert np.min(np.hypot(cols - c[0], rows + r.TOP - c[1])) < 6


def test_a_long_warning_is_wrapped_within_the_frame():
    """A warning longer than the frame is wide: every word is drawn (in lines), none past
    the right edge, all of it in the panel above the scene (it ran off the edge before)."""
    words = " ".join(f"word{k}" for k in range(40))
    ev = slide()
    r = Renderer(ev, look=Look(size=(640, 360), warnings=((0.0, "SECONDARY " + words),)))
    img = r.frame(len(ev) - 1)
    red = near(img, COLORS["warning"], tol=60)
    rows, cols = np.nonzero(red)
    assert len(rows) > 200 and cols.max() <= r.size[0] - 10
    assert rows.max() < r.TOP - 2                       # in the panel, above the scene
    lines = r.warning_lines("SECONDARY " + words, 10)
    assert len(lines) >= 3 and " ".join(lines) == "SECONDARY " + words
    assert r.TOP >= Renderer.TOP + (len(lines) - 1) * r.small_glyphs.height
    assert len({int(y) for y in rows // r.small_glyphs.height}) >= len(lines)
    fitted = Renderer(ev, look=Look(warnings=((0.0, words),)))       # the frame grows
    assert fitted.size[1] - fitted.TOP == Renderer(ev).size[1] - Renderer.TOP


def test_a_word_longer_than_the_frame_is_broken_within_it():
    r = Renderer(slide(), look=Look(size=(320, 240), warnings=((0.0, "x" * 200),)))
    lines = r.warning_lines("x" * 200, 10)
    assert "".join(lines) == "x" * 200
    assert all(r.small_glyphs.width(line) <= r.size[0] - 20 for line in lines)


@pytest.mark.parametrize("fps", [20, 24, 25, 30, 60])
def test_the_gif_keeps_real_time(tmp_path, fps):
    """A GIF counts frame times in hundredths of a second: 30 fps stored as 3 of them
    played 10 % fast. The GIF's total duration matches the event's frames within 1 %."""
    from PIL import Image

    from comparisons.animation.render import gif_durations, write_animation

    n = 3 * fps + 1                                     # 3 s of frames at fps
    ev = slide(n=n, slide_from=n // 2)
    info = write_animation(Renderer(ev, look=Look(size=(320, 240))), tmp_path / "a.mp4",
                           fps=fps, gif=tmp_path / "a.gif", progress=False, gif_scale=0.5)
    total = 0
    with Image.open(info.gif) as gif:
        for k in range(gif.n_frames):
            gif.seek(k)
            total += gif.info["duration"]
    assert total / 1000 == pytest.approx(n / fps, rel=0.01)
    assert sum(gif_durations(n, fps)) == round(100 * n / fps) * 10


@pytest.mark.parametrize("at", ["frame", "close"])
def test_an_interrupt_waits_for_the_frame_and_for_the_encoder(tmp_path, monkeypatch, at):
    """A SIGTERM while a frame went down ffmpeg's pipe left ffmpeg part of a frame, and it
    printed its own error under pim's one line; now the interrupt is raised once the frame
    is whole, after the encoder was closed and waited for, and nothing is left behind."""
    import imageio.v2

    from pim.io.process import Interrupts, Terminated

    seen = []

    class Encoder:
        def __init__(self, path, *args, **kwargs):
            open(path, "wb").close()

        def append_data(self, frame):
            seen.append("frame")
            if at == "frame" and seen.count("frame") == 2:
                os.kill(os.getpid(), signal.SIGTERM)
            seen.append("whole")

        def close(self):
            seen.append("closing")
            if at == "close":
                os.kill(os.getpid(), signal.SIGTERM)
            seen.append("closed")

    monkeypatch.setattr(imageio.v2, "get_writer", Encoder)
    renderer = Renderer(slide(n=4), look=Look(size=(320, 180)))
    with Interrupts().installed() as interrupts, pytest.raises(Terminated):
        write_animation(renderer, tmp_path / "a.mp4", progress=False)
    frames = 2 if at == "frame" else len(renderer)
    assert seen == ["frame", "whole"] * frames + ["closing", "closed"]
    assert interrupts.received == [signal.SIGTERM]
    assert list(tmp_path.iterdir()) == []
