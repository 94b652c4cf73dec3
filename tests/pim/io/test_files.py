"""pim/io/files.py: writes are atomic: a failure leaves the old file and no temporary."""

import pytest
from matplotlib.figure import Figure

from pim.io.files import atomic_path, atomic_paths, check_complete, save_figure, write_text


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
    from pim_cli.main import main

    assert main(["draw", "ricsac9", "--out", str(tmp_path / "x.xyz")]) == 2
    err = capsys.readouterr().err
    assert ".xyz" in err and ".png" in err and not list(tmp_path.iterdir())
@pytest.mark.parametrize("suffix, good", [
    (".png", b"\x89PNG\r\n\x1a\n" + b"data" + b"\0\0\0\0IEND\xaeB`\x82"),
    (".gif", b"GIF89a" + b"data" + b";"),
    (".mp4", (16).to_bytes(4, "big") + b"ftypisom" + b"\0" * 4
     + (8).to_bytes(4, "big") + b"mdat" + (8).to_bytes(4, "big") + b"moov")])
def test_a_cut_file_is_an_error_and_nothing_is_written(tmp_path, suffix, good):
    """Issue 22: a full disk left a truncated MP4 under its final name (exit 0)."""
    target = tmp_path / f"a{suffix}"
    with atomic_path(target) as tmp:
        tmp.write_bytes(good)
    assert target.read_bytes() == good
    with pytest.raises(OSError, match="incomplete"), atomic_path(target) as tmp:
        tmp.write_bytes(good[:-3])
    assert target.read_bytes() == good           # the old file stays
    assert [p.name for p in tmp_path.iterdir()] == [target.name]
    check_complete(target)


def test_a_real_encoder_output_passes_and_its_truncation_fails(tmp_path):
    import imageio.v2 as imageio
    import numpy as np

    path = tmp_path / "v.mp4"
    with atomic_path(path) as tmp:
        writer = imageio.get_writer(tmp, format="FFMPEG", fps=10, codec="libx264",
                                    macro_block_size=2, ffmpeg_log_level="error")
        for k in range(5):
            writer.append_data(np.full((16, 16, 3), 40 * k, np.uint8))
        writer.close()
    data = path.read_bytes()
    path.write_bytes(data[: len(data) - 20])
    with pytest.raises(OSError, match="incomplete"):
        check_complete(path)


def test_a_set_of_files_is_renamed_only_when_every_one_is_complete(tmp_path):
    """Files that belong together are one set: a cut GIF leaves neither file, the old one as
    it was and no temporary."""
    md = write_text(tmp_path / "a.md", "old")
    with pytest.raises(OSError, match="incomplete"), atomic_paths(
            md, tmp_path / "a.gif") as (t_md, t_gif):
        t_md.write_text("new")
        t_gif.write_bytes(b"GIF89a" + b"cut")          # no trailer byte
    assert md.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.md"]
    with atomic_paths(md, tmp_path / "b.txt") as (t_a, t_b):
        t_a.write_text("new")
        t_b.write_text("b")
    assert md.read_text() == "new" and (tmp_path / "b.txt").read_text() == "b"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.md", "b.txt"]


def test_a_full_disk_names_the_file_as_the_user_knows_it(tmp_path, capsys):
    """An OSError without a file name (a full disk on a write) or about the temporary file
    names the target: "error: cannot write No space left on device" named nothing."""
    import errno

    target = tmp_path / "scene.png"
    with pytest.raises(OSError) as info, atomic_path(target):
        raise OSError(errno.ENOSPC, "No space left on device")
    assert info.value.filename == str(target) and info.value.errno == errno.ENOSPC
    with pytest.raises(OSError) as info, atomic_paths(target, tmp_path / "a.gif") as (tmp, _):
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp))
    assert info.value.filename == str(target)
    with pytest.raises(FileNotFoundError) as info, atomic_path(target):
        open(tmp_path / "missing.toml")                      # another file: as it was
    assert info.value.filename == str(tmp_path / "missing.toml")
    assert list(tmp_path.iterdir()) == []
