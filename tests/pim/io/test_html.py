"""pim.io.html: the blocks of the self-contained HTML reports (escaping, inline data,
alignment, print style) -- without a browser (tests/comparisons/report/test_html.py drives one)."""

import base64
import re

import imageio.v2 as imageio
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from pim.io import html as h

PNG = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGA"
                       "hKmMIQAAAABJRU5ErkJggg==")


@given(st.text() | st.builds(lambda a, b: f"[{a}]({b})", st.text(), st.text()))
def test_text_never_becomes_markup(text):
    out = h.inline(text)
    assert "<" not in re.sub(r'</?(code|strong)>|<a href="[\w.-][\w./-]*">|</a>', "", out)
    assert '"' not in h.esc(text) and "'" not in h.esc(text)


def test_links_go_to_files_beside_the_page_only():
    assert h.inline("see [t.csv](t.csv)") == 'see <a href="t.csv">t.csv</a>'
    for url in ("javascript:alert(1)", "//evil.example/x", "/etc/passwd", "a b"):
        assert "<a" not in h.inline(f"[x]({url})"), url


def test_a_png_states_its_smallest_text(tmp_path):
    from matplotlib.figure import Figure

    from pim.io.files import save_figure

    fig = Figure(figsize=(3, 2), layout="constrained")
    ax = fig.subplots()
    ax.set_title("title", fontsize=12)
    ax.plot([0, 1], label="x")
    ax.legend(fontsize=7)
    path = save_figure(fig, tmp_path / "f.png", dpi=100)
    width, height, text = h.png_text_px(path.read_bytes())
    assert (width, height) == (300, 200) and text == pytest.approx(7 * 100 / 72, rel=1e-3)
    out = h.figure(path, alt="f")
    assert 'width="300" height="200"' in out and 'data-text-px="9.722"' in out
    assert h.png_text_px(PNG)[2] is None and "data-text-px" not in h.figure(PNG, alt="x")


def test_inline_marks_render_after_escaping():
    assert h.inline("run `pim fit <case>` **now**") == \
        "run <code>pim fit &lt;case&gt;</code> <strong>now</strong>"


def test_table_escapes_and_right_aligns_numbers():
    out = h.table(("name <x>", "value [m/s]"), [("<b>a</b>", "1.5e-07"), ("b & c", "-2")],
                  title="T <1>", note="CSV: `t.csv`")
    assert "<b>" not in out and "&lt;b&gt;a&lt;/b&gt;" in out and "b &amp; c" in out
    assert "<th>name &lt;x&gt;</th>" in out and '<th class="num">value [m/s]</th>' in out
    assert '<td class="num">1.5e-07</td>' in out
    assert "<caption>T &lt;1&gt;" in out and "<code>t.csv</code>" in out


def test_a_text_column_stays_left_aligned():
    out = h.table(("a",), [("1",), ("x",)])
    assert 'class="num"' not in out


def test_columns_no_group_names_are_shown_last():
    parts = h.split_columns(("k", "a [m]", "b", "new"), (("A", ("a",)), ("B", ("b",))), "k")
    assert parts == [("A", ["k", "a [m]"]), ("B", ["k", "b"]), ("Other columns", ["k", "new"])]


def test_a_split_table_keeps_every_row_and_leads_each_part_with_the_key():
    out = h.split_table(("k", "a", "b"), [("r1", "1", "2"), ("r2", "3", "4")],
                        (("A", ("a",)), ("B", ("b",))), "k", note="n", id="t")
    assert out.count("<table") == 2 and 'id="t-1"' in out and 'id="t-2"' in out
    assert out.count("<td>r1</td>") == 2 and out.count("<td>r2</td>") == 2
    assert out.count('class="note"') == 1


def test_figure_inlines_the_image_bytes(tmp_path):
    (tmp_path / "p.png").write_bytes(PNG)
    out = h.figure(tmp_path / "p.png", alt='a "plot"', caption="c")
    src = re.search(r'src="data:image/png;base64,([^"]+)"', out).group(1)
    assert base64.b64decode(src) == PNG
    assert 'alt="a &quot;plot&quot;"' in out


@pytest.fixture(scope="module")
def mp4(tmp_path_factory):
    """A 12-frame H.264 video whose frames are uniformly grey 0, 20, ..., 220."""
    path = tmp_path_factory.mktemp("video") / "v.mp4"
    with imageio.get_writer(path, format="FFMPEG", fps=6, codec="libx264",
                            pixelformat="yuv420p", macro_block_size=2,
                            ffmpeg_log_level="error") as w:
        for i in range(12):
            w.append_data(np.full((32, 48, 3), 20 * i, np.uint8))
    return path


def test_video_is_inline_with_its_stated_duration(mp4):
    out = h.video(mp4, frames=12, fps=6, size=(48, 32), still=PNG, caption="x")
    assert 'data-duration="2"' in out and "12 frames at 6 fps (2.00 s)" in out
    src = re.search(r'<video[^>]* src="data:video/mp4;base64,([^"]+)"', out).group(1)
    assert base64.b64decode(src) == mp4.read_bytes()
    assert "controls" in out and 'class="print-only"' in out and "poster=" in out


def test_still_frame_is_the_frame_asked_for(mp4):
    import io

    from PIL import Image

    grey = np.asarray(Image.open(io.BytesIO(h.still_frame(mp4, 0.5))).convert("L"))
    assert grey.shape == (32, 48)
    assert abs(float(grey.mean()) - 120) < 8       # frame 6 of 12 is grey 120


def test_page_is_self_contained_and_printable():
    out = h.page("A <title>", [h.section("S", h.paragraph("p"), id="s")],
                 subtitle="sub", contents=[("s", "S")])
    assert out.startswith("<!DOCTYPE html>") and "<title>A &lt;title&gt;</title>" in out
    assert '<a href="#s">S</a>' in out and '<section id="s"' in out
    assert not re.search(r"(src|href)=\"(https?:)?//", out) and "<link" not in out
    assert "<script" not in out and "@import" not in out and "url(" not in out
    media = out.split("@media print", 1)[1]
    assert "break-before:page" in media and "video{display:none" in media
