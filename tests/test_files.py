"""pim/io/files.py: writes are atomic: a failure leaves the old file and no temporary."""

import pytest
from matplotlib.figure import Figure

from pim.io.files import atomic_path, save_figure, write_text


def test_failed_write_keeps_the_old_file_and_no_temporary(tmp_path):
    target = write_text(tmp_path / "a.md", "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("interrupted")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.md"]


def test_save_figure_needs_a_format_and_writes_it(tmp_path):
    fig = Figure()
    fig.add_subplot().plot([0, 1], [0, 1])
    with pytest.raises(ValueError, match="suffix"):
        save_figure(fig, tmp_path / "plot")
    path = save_figure(fig, tmp_path / "plot.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_an_unknown_image_format_is_an_input_error(tmp_path, capsys):
    """Issue 21 point 7: with only InputError turned into exit 2, matplotlib's ValueError
    for '.xyz' must become one first (else a traceback)."""
    from pim.cli import main

    assert main(["draw", "ricsac9", "--out", str(tmp_path / "x.xyz")]) == 2
    err = capsys.readouterr().err
    assert ".xyz" in err and ".png" in err and not list(tmp_path.iterdir())
