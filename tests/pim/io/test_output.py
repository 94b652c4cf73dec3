"""pim/io/output.py: output folders as transactions (issue 22): whole or not at all, one run
at a time, nothing deleted outside the folder, no temporary litter."""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from pim.io.output import MARKER, OutputError, output_folder, rebase


def tree(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def litter(parent):
    return [p.name for p in parent.iterdir() if ".pim-" in p.name]


def write_run(folder, files):
    with output_folder(folder) as tmp:
        for name, text in files.items():
            (tmp / name).parent.mkdir(parents=True, exist_ok=True)
            (tmp / name).write_text(text)
    return folder


def test_a_run_replaces_the_folder_whole(tmp_path):
    out = write_run(tmp_path / "out", {"a.csv": "1", "animation.mp4": "old video"})
    write_run(out, {"a.csv": "2", "plots/p.png": "x"})
    files = tree(out)
    assert files.pop(MARKER)
    assert files == {"a.csv": b"2", "plots/p.png": b"x"}       # the old MP4 is gone
    assert litter(tmp_path) == []


@pytest.mark.parametrize("error", [KeyboardInterrupt, OSError, RuntimeError])
def test_an_error_keeps_the_old_run_and_leaves_no_litter(tmp_path, error):
    """(An OSError while the run is written becomes an OutputError naming the folder.)"""
    out = write_run(tmp_path / "out", {"a.csv": "1"})
    before = tree(out)
    with pytest.raises(OutputError if error is OSError else error), output_folder(out) as tmp:
        (tmp / "a.csv").write_text("half")
        (tmp / "new.png").write_text("x")
        raise error()
    assert tree(out) == before
    assert litter(tmp_path) == []


def test_a_first_run_that_fails_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt), output_folder(tmp_path / "out") as tmp:
        (tmp / "a.csv").write_text("half")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_a_second_run_into_a_busy_folder_fails_clearly(tmp_path):
    out = tmp_path / "out"
    with output_folder(out) as tmp:
        (tmp / "first").write_text("1")
        with pytest.raises(OutputError, match="another pim run is writing"), \
                output_folder(out):
            pass
    assert (out / "first").exists()
    with output_folder(out):      # the lock is free again, and its file gone
        pass
    assert litter(tmp_path) == []


def test_the_lock_holds_across_processes(tmp_path):
    out = tmp_path / "out"
    code = textwrap.dedent(f"""
        import sys, time
        from pim.io.output import output_folder
        with output_folder({str(out)!r}) as tmp:
            print("locked", flush=True)
            time.sleep(30)
    """)
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "locked"
        with pytest.raises(OutputError, match="another pim run"), output_folder(out):
            pass
    finally:
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=30)
    assert litter(tmp_path) == []          # the interrupted holder removed its folder


def test_a_folder_of_the_users_own_files_is_never_replaced(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    (home / "thesis.tex").write_text("years of work")
    with pytest.raises(OutputError, match="pim did not write"), output_folder(home):
        pass
    assert (home / "thesis.tex").read_text() == "years of work"
    empty = tmp_path / "empty"
    empty.mkdir()
    write_run(empty, {"a": "1"})           # an empty folder is fine


def test_stale_temporary_folders_of_killed_runs_are_swept(tmp_path):
    stale = tmp_path / ".out.pim-tmp-abc123"
    stale.mkdir()
    (stale / "animation.mp4").write_text("half")
    unrelated = tmp_path / ".other.pim-tmp-abc123"
    unrelated.mkdir()
    write_run(tmp_path / "out", {"a": "1"})
    assert not stale.exists() and unrelated.exists()


def test_below_a_file_or_unwritable_is_an_output_error(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(OutputError, match="is a file"), output_folder(tmp_path / "f" / "o"):
        pass
    if os.geteuid() != 0:
        ro = tmp_path / "ro"
        ro.mkdir(mode=0o555)
        with pytest.raises(OutputError, match="not writable"), output_folder(ro / "o"):
            pass


def test_rebase_maps_temporary_paths_to_the_final_folder(tmp_path):
    assert rebase([tmp_path / "t" / "plots" / "a.png"], tmp_path / "t", "out") == [
        Path("out/plots/a.png")]


def test_a_run_whose_interrupt_was_swallowed_is_not_swapped_in(tmp_path):
    """The run's Interrupts handler remembers the signal (pim.io.process.signal_received):
    the block ended normally, yet the old run stays and the interrupt is raised."""
    from pim.io.process import Interrupts

    out = write_run(tmp_path / "out", {"a.csv": "old"})
    before = tree(out)
    with Interrupts().installed(), pytest.raises(KeyboardInterrupt):
        with output_folder(out) as tmp:
            (tmp / "a.csv").write_text("new")
            try:
                os.kill(os.getpid(), signal.SIGINT)
            except KeyboardInterrupt:
                pass                                # swallowed on its way
    assert tree(out) == before
    assert litter(tmp_path) == []


def test_a_shared_folder_gets_the_runs_files_and_keeps_the_others(tmp_path):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "README.md").write_text("mine")
    (docs / "hard-cases.md").write_text("old")
    with pytest.raises(KeyboardInterrupt), output_folder(docs, merge=True) as tmp:
        (tmp / "hard-cases.md").write_text("half")
        raise KeyboardInterrupt
    assert (docs / "hard-cases.md").read_text() == "old"
    with output_folder(docs, merge=True) as tmp:
        (tmp / "hard-cases.md").write_text("new")
        (tmp / "hard-cases.csv").write_text("new")
    assert tree(docs) == {"README.md": b"mine", "hard-cases.md": b"new",
                          "hard-cases.csv": b"new"}
    assert litter(tmp_path) == []


def test_the_current_directory_is_never_replaced(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    with pytest.raises(OutputError, match="current directory"), output_folder("."):
        pass
    assert work.is_dir()


def test_a_command_that_fails_midway_keeps_the_earlier_run(tmp_path, monkeypatch, capsys):
    """`pim plot` (as every folder-writing command) through output_folder: a full disk half
    way leaves the earlier run whole, one line, exit 2."""
    import errno

    import pim.plotting.sheet as sheet
    from pim_cli.main import main

    out = tmp_path / "plots"
    assert main(["plot", "hard-pole", "--out", str(out), "--format", "png"]) == 0
    before = tree(out)
    real = sheet.write_plots

    def disk_full(case, result, folder, **kwargs):
        real(case, result, folder, **kwargs)
        raise OSError(errno.ENOSPC, "No space left on device", str(Path(folder) / "x.png"))

    monkeypatch.setattr(sheet, "write_plots", disk_full)
    capsys.readouterr()
    assert main(["plot", "hard-pole", "--out", str(out), "--format", "png", "--units",
                 "us"]) == 2
    errors = [line for line in capsys.readouterr().err.splitlines() if "error" in line]
    assert len(errors) == 1 and "No space left" in errors[0]
    assert tree(out) == before
    assert litter(tmp_path) == []


# Issue 28: a rerun into a folder pim wrote earlier, to which the user had added notes.txt,
# deleted notes.txt with the folder.
def test_a_rerun_keeps_what_the_user_put_into_the_folder_and_says_so(tmp_path):
    out = write_run(tmp_path / "out", {"a.csv": "1", "animation.mp4": "old video"})
    (out / "notes.txt").write_text("my notes")
    (out / "photos").mkdir()
    (out / "photos" / "scene.jpg").write_text("jpeg")
    (out / "empty").mkdir()
    (out / "link").symlink_to("notes.txt")
    said = []
    with output_folder(out, say=said.append) as tmp:
        (tmp / "a.csv").write_text("2")
    files = tree(out)
    assert files.pop(MARKER) and files.pop("link") == b"my notes"      # the link, followed
    assert files == {"a.csv": b"2", "notes.txt": b"my notes", "photos/scene.jpg": b"jpeg"}
    assert (out / "empty").is_dir() and os.readlink(out / "link") == "notes.txt"
    assert said == [f"--out {out}: kept empty/, link, notes.txt, photos/scene.jpg (pim did "
                    f"not write them)"]
    write_run(out, {"a.csv": "3"})                       # and the next run keeps them too
    assert (out / "notes.txt").read_text() == "my notes" and litter(tmp_path) == []


def test_the_kept_note_goes_to_stderr_by_default(tmp_path, capfd):
    out = write_run(tmp_path / "out", {"a.csv": "1"})
    (out / "notes.txt").write_text("my notes")
    write_run(out, {"a.csv": "2"})
    assert capfd.readouterr().err == f"note: --out {out}: kept notes.txt (pim did not write it)\n"


def test_a_file_pim_wrote_and_the_user_changed_refuses_the_rerun_before_the_work(tmp_path):
    out = write_run(tmp_path / "out", {"report.md": "pim's", "a.csv": "1"})
    (out / "report.md").write_text("pim's, with my comments")
    before = tree(out)
    with pytest.raises(OutputError) as err, output_folder(out):
        pytest.fail("the work ran")
    assert str(err.value) == (f"--out {out}: report.md changed since pim wrote it; a rerun "
                              "replaces what pim wrote: move or rename it, then run again")
    assert tree(out) == before and litter(tmp_path) == []


def test_a_file_of_the_users_named_as_a_new_output_leaves_the_folder_as_it_was(tmp_path):
    out = write_run(tmp_path / "out", {"a.csv": "1"})
    (out / "animation.mp4").write_text("made by hand")
    before = tree(out)
    with pytest.raises(OutputError, match="this run writes animation.mp4, which pim did not "
                                          "write there before"), output_folder(out) as tmp:
        (tmp / "animation.mp4").write_text("pim's")
    assert tree(out) == before and litter(tmp_path) == []


def test_a_folder_whose_marker_lists_no_files_keeps_all_the_new_run_does_not_write(tmp_path):
    """Written before the marker listed the run's files: pim cannot tell the user's files
    from its own, so it deletes none of them (a namesake of a new file is replaced)."""
    out = tmp_path / "out"
    out.mkdir()
    (out / MARKER).write_text("written by pim compare; the next pim run into this folder "
                              "replaces it whole\n")
    (out / "a.csv").write_text("old")
    (out / "notes.txt").write_text("my notes")
    said = []
    with output_folder(out, say=said.append) as tmp:
        (tmp / "a.csv").write_text("new")
    assert (out / "a.csv").read_text() == "new" and (out / "notes.txt").read_text() == "my notes"
    assert said == [f"--out {out}: kept notes.txt (pim did not write it)"]


def test_a_full_disk_names_the_output_folder_and_file(tmp_path, capsys):
    """"error: cannot write No space left on device" named no output (issue 33 point 11):
    an OSError without a file name names the folder; one about a temporary file names the
    file as it would be in the folder."""
    import errno

    out = tmp_path / "out"
    with pytest.raises(OutputError) as info, output_folder(out) as tmp:
        raise OSError(errno.ENOSPC, "No space left on device")
    text = str(info.value)
    assert text.startswith(f"--out {out}: cannot write (No space left on device)")
    assert "nothing was written" in text
    with pytest.raises(OutputError) as info, output_folder(out) as tmp:
        raise OSError(errno.ENOSPC, "No space left on device", str(tmp / "plots" / "x.png"))
    assert f"cannot write {out / 'plots' / 'x.png'} (No space left on device)" in \
        str(info.value)
    assert litter(tmp_path) == []
    outside = tmp_path / "input.toml"                # an input's error stays as it is
    with pytest.raises(FileNotFoundError), output_folder(out):
        outside.read_text()


def test_a_read_only_folder_or_mount_point_is_said_before_the_work(tmp_path, monkeypatch):
    """A read-only mount as the output folder was reported as "Device or resource busy"
    after the work (the swap's rename): refused before it, naming the folder and why."""
    import os

    out = tmp_path / "ro"
    out.mkdir()
    real = os.statvfs

    class ReadOnly:
        def __init__(self, st):
            self.f_flag = st.f_flag | os.ST_RDONLY

    monkeypatch.setattr(os, "statvfs", lambda p: ReadOnly(real(p)) if str(p) == str(out)
                        else real(p))
    with pytest.raises(OutputError, match=rf"--out {out}: the folder {out} is on a read-only "
                                          r"file system \(not writable\)"):
        with output_folder(out):
            pass
    monkeypatch.setattr(os, "statvfs", real)
    monkeypatch.setattr(os.path, "ismount", lambda p: str(p) == str(out))
    with pytest.raises(OutputError, match=r"a mount point; .* give a folder inside it"):
        with output_folder(out):
            pass
