"""Output folders as transactions: a run is written whole or not at all, one run at a time.

Every command that writes a folder (``pim compare``, ``assumptions``, ``validate``,
``reconstruct``, ``plot``, ``hard-cases``, ``speed-error``) writes it through
:func:`output_folder`:

1. A lock file beside the folder (``.NAME.pim-lock``, an ``fcntl.flock`` lock) makes a second
   run into the same folder fail at once with :class:`OutputError` (one line, exit code 2 on
   the command line) instead of mixing its files with the first run's.
2. The run writes into a temporary sibling folder (``.NAME.pim-tmp-XXXX``).
3. At the end the temporary folder is swapped in for the old one (``renameat2`` with
   ``RENAME_EXCHANGE`` where the kernel has it: one atomic step), with SIGINT and SIGTERM held
   back, and the old run is deleted. The folder holds the new run whole: a file of the old run
   that this run does not write (an MP4 after ``--no-animation``) is gone.

Any error or interrupt before the swap (Ctrl-C, SIGTERM, a full disk, an encoder that fails)
deletes the temporary folder and leaves the old run as it was. Nothing outside the folder and
its own ``.NAME.pim-*`` siblings is ever deleted. Each run leaves a marker file
(:data:`MARKER`) in its folder listing the files it wrote with their SHA-256; an existing
non-empty folder without one (the user's own files) is never replaced: that is an
:class:`OutputError` too.

Nothing a user put into a folder pim wrote is deleted: a file the marker does not list
(``notes.txt`` added after the run) is kept, linked into the new run before the swap, and
named on stderr ("kept notes.txt (pim did not write it)"); a file pim wrote that was changed
since (an edited ``report.md``) makes the rerun an :class:`OutputError` before any work,
naming it; so does a kept file of the same name as one the new run writes (at the end, the
old run left as it was). A folder written before the marker listed files (its marker without
a list, or :data:`LEGACY_MARKERS`) cannot tell the user's files from its own: the files the
new run does not write are kept and named, never deleted.

A folder shared by design (``pim speed-error --out docs``, ``pim hard-cases --out docs``)
is written with ``merge=True``: the same lock, temporary folder and cleanup, but at the end
the run's files are moved into the folder together, replacing files of the same name and
keeping the others.

Single files (``pim animate --out x.mp4``, ``pim draw``) are written by
:func:`pim.io.files.atomic_path`, which checks the written file before renaming it.

The signals (held back during the swap, a swallowed interrupt noticed before it) are
:mod:`pim.io.process`'s, the process side of a run.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import errno
import fcntl
import hashlib
import os
import shutil
import sys
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from .process import held_signals, signal_received

__all__ = ["output_folder", "OutputError", "MARKER", "rebase"]

#: File in every output folder marking it as a pim run (replaceable by the next run).
MARKER = ".pim-run"
#: Marker of the folders written before MARKER existed (its content is never read).
LEGACY_MARKERS = (".pim-compare-files",)


class OutputError(ValueError):
    """An output folder that cannot be written (busy, a file, not pim's, not writable)."""


def _target(path, option: str) -> Path:
    """The absolute folder ``path`` (symbolic links resolved), checked to be creatable."""
    path = Path(os.path.realpath(Path(path).expanduser()))
    for parent in [path, *path.parents]:
        if parent.exists() and not parent.is_dir():
            raise OutputError(f"{option} {path}: {parent} is a file, not a folder")
    if path == path.parent:
        raise OutputError(f"{option} {path}: the root folder cannot be an output folder")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{option} {path}: cannot create the folder ({exc.strerror})") \
            from None
    for folder in (path.parent, path) if path.is_dir() else (path.parent,):
        why = _unwritable(folder)
        if why:
            raise OutputError(f"{option} {path}: the folder {folder} {why}")
    return path


def _unwritable(folder: Path) -> str | None:
    """Why files cannot be written in ``folder`` (a read-only file system, no permission),
    or None."""
    try:
        if os.statvfs(folder).f_flag & os.ST_RDONLY:
            return "is on a read-only file system (not writable)"
    except OSError:
        pass
    if not os.access(folder, os.W_OK | os.X_OK):
        return "is not writable (no permission)"
    return None


def _check_not_a_mount(path: Path, option: str) -> None:
    """A run is swapped in by renaming folders beside ``path``: a mount point cannot be
    renamed (the kernel answers "Device or resource busy"), so it is refused up front."""
    if path.is_dir() and os.path.ismount(path):
        raise OutputError(f"{option} {path}: a mount point; pim writes a run beside the "
                          f"output folder and renames it into place, which a mount point "
                          f"cannot take: give a folder inside it (e.g. {option} "
                          f"{path / 'run'})")


def _lock(path: Path, option: str) -> int:
    """Take the lock of folder ``path``; return its file descriptor (see :func:`_unlock`)."""
    lock = path.parent / f".{path.name}.pim-lock"
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise OutputError(f"{option} {path}: cannot create the lock file {lock} "
                              f"({exc.strerror})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise OutputError(f"{option} {path}: another pim run is writing this folder "
                              f"(lock {lock.name}); wait for it to end or choose another "
                              "folder") from None
        # The holder before us may have removed the lock file after we opened it: then our
        # lock is on a deleted file and we try again.
        try:
            if os.stat(lock).st_ino == os.fstat(fd).st_ino:
                return fd
        except FileNotFoundError:
            pass
        os.close(fd)


def _unlock(path: Path, fd: int) -> None:
    """Remove the lock file (while still holding it) and release the lock."""
    with contextlib.suppress(FileNotFoundError):
        os.unlink(path.parent / f".{path.name}.pim-lock")
    os.close(fd)


def _sweep(path: Path) -> None:
    """Delete temporary siblings that killed runs left (we hold the lock: none is in use)."""
    for pattern in (f".{path.name}.pim-tmp-*", f".{path.name}.pim-old-*"):
        for stale in path.parent.glob(pattern):
            if stale.is_dir() and not stale.is_symlink():
                shutil.rmtree(stale, ignore_errors=True)


def _manifest(folder: Path) -> dict | None:
    """The files the run in ``folder`` wrote, path -> SHA-256 (its :data:`MARKER`'s lines
    ``<sha256>  <path>``); None for a folder whose marker lists none (written before it did)."""
    try:
        lines = (folder / MARKER).read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError):
        return None
    listed = {}
    for line in lines:
        digest, sep, name = line.partition("  ")
        if sep and not line.startswith("#"):
            listed[name] = digest
    return listed or None


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            digest.update(chunk)
    return digest.hexdigest()


def _entries(folder: Path) -> list[str]:
    """Every file, symbolic link and empty folder below ``folder`` (relative POSIX paths; an
    empty folder ends in "/"), the marker left out; symbolic links are not followed."""
    out = []
    for root, dirs, files in os.walk(folder):
        here = Path(root)
        out += [(here / name).relative_to(folder).as_posix()
                for name in files + [d for d in dirs if (here / d).is_symlink()]]
        if not dirs and not files and here != folder:
            out.append(here.relative_to(folder).as_posix() + "/")
    return sorted(e for e in out if e != MARKER)


def _names(names: list[str], most: int = 5) -> str:
    shown = ", ".join(names[:most])
    return shown + (f" and {len(names) - most} more" if len(names) > most else "")


def _check_unchanged(path: Path, option: str) -> None:
    """An OutputError naming the files pim wrote into ``path`` that were changed since."""
    changed = [name for name, digest in (_manifest(path) or {}).items()
               if (path / name).is_file() and not (path / name).is_symlink()
               and _sha256(path / name) != digest]
    if changed:
        them = "it" if len(changed) == 1 else "them"
        raise OutputError(f"{option} {path}: {_names(changed)} changed since pim wrote {them}; "
                          f"a rerun replaces what pim wrote: move or rename {them}, then run "
                          f"again")


def _check_replaceable(path: Path, option: str) -> None:
    """An existing folder may be replaced only when it is empty or a pim run, none of whose
    files was changed since."""
    if not path.exists():
        return
    cwd = Path(os.path.realpath(os.getcwd()))
    if cwd == path or path in cwd.parents:
        raise OutputError(f"{option} {path}: the folder holds the current directory; pim "
                          "replaces its output folder whole, so choose another folder")
    if path.is_symlink() or not path.is_dir():
        raise OutputError(f"{option} {path}: not a folder")
    if any(path.iterdir()) and not any((path / m).is_file()
                                       for m in (MARKER, *LEGACY_MARKERS)):
        raise OutputError(f"{option} {path}: the folder holds files that pim did not write "
                          f"(no {MARKER} file); pim replaces its output folder whole, so "
                          "choose a new or empty folder")
    _check_unchanged(path, option)


def _keep(path: Path, tmp: Path, option: str) -> list[str]:
    """Link what the user put into the old run ``path`` (what its manifest does not list)
    into the finished run ``tmp``: hard links, else copies, so the old run stays whole until
    the swap. Returns their names. One of the same name as a file the run wrote is an
    OutputError (nothing lost: the old run is left as it was). Of a run whose marker lists
    no files, what the new run writes replaces its namesake and the rest is kept."""
    if not path.is_dir():
        return []
    listed = _manifest(path)
    theirs = [e for e in _entries(path) if e not in (listed or {}) and e not in LEGACY_MARKERS]

    def taken(entry: str) -> bool:
        there = tmp / entry.rstrip("/")
        return there.exists() and not (entry.endswith("/") and there.is_dir())

    if listed is None:
        theirs = [e for e in theirs if not taken(e)]
    clash = [e for e in theirs if taken(e)]
    if clash:
        raise OutputError(f"{option} {path}: this run writes {_names(clash)}, which pim did "
                          f"not write there before (a file of yours?); move or rename it, "
                          f"then run again (the folder is left as it was)")
    for entry in theirs:
        _link(path / entry.rstrip("/"), tmp / entry.rstrip("/"), entry.endswith("/"))
    return theirs


def _link(src: Path, dst: Path, folder: bool) -> None:
    """``src`` at ``dst``: a folder made, a symbolic link copied as one, a file hard-linked
    (copied where links are not allowed)."""
    dst.parent.mkdir(parents=True, exist_ok=True)
    if folder:
        dst.mkdir(exist_ok=True)
    elif src.is_symlink():
        os.symlink(os.readlink(src), dst)
    else:
        try:
            os.link(src, dst)
        except OSError:
            shutil.copy2(src, dst)


def _write_marker(tmp: Path, command: str) -> None:
    """The marker: who wrote the folder, then ``<sha256>  <path>`` of each file it wrote."""
    lines = [f"# written by {command}; the next pim run into this folder replaces the files "
             f"listed below and keeps any other"]
    lines += [f"{_sha256(tmp / e)}  {e}" for e in _entries(tmp)
              if not e.endswith("/") and not (tmp / e).is_symlink()]
    (tmp / MARKER).write_text("\n".join(lines) + "\n", encoding="utf-8")


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap folders ``a`` and ``b`` in one atomic step (Linux renameat2); False if unsupported."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c"), use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError, TypeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                          ctypes.c_uint]
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(b))


def _merge_in(tmp: Path, path: Path) -> None:
    """Move every file of the finished run ``tmp`` into ``path`` (replacing files of the
    same name, keeping the others); delete ``tmp``. Run with signals held back."""
    path.mkdir(exist_ok=True)
    for src in sorted(tmp.rglob("*")):
        if src.is_file():
            dst = path / src.relative_to(tmp)
            dst.parent.mkdir(parents=True, exist_ok=True)
            os.replace(src, dst)
    shutil.rmtree(tmp, ignore_errors=True)


def _swap_in(tmp: Path, path: Path) -> None:
    """Put the finished run ``tmp`` at ``path``; delete the old run (signals held back)."""
    if not path.exists():
        os.rename(tmp, path)
        return
    if _exchange(tmp, path):
        shutil.rmtree(tmp, ignore_errors=True)          # tmp now holds the old run
        return
    old = Path(tempfile.mkdtemp(prefix=f".{path.name}.pim-old-", dir=path.parent))
    os.rename(path, old / "run")
    os.rename(tmp, path)
    shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def output_folder(path, option: str = "--out", *, command: str = "pim",
                  merge: bool = False, say=None) -> Iterator[Path]:
    """Write a run into a temporary folder and swap it in for ``path`` when the block ends.

    Parameters
    ----------
    path : path
        The output folder (created with its parents; an existing one is replaced whole when
        it is empty or was written by pim).
    option : str
        The command-line option named in error messages.
    command : str
        Written into the folder's marker file (:data:`MARKER`).
    merge : bool
        For a folder shared by design (``pim speed-error --out docs``): at the end the run's
        files are moved into ``path`` all together (signals held back), replacing files of
        the same name and keeping every other file; no marker. The lock, the temporary
        folder and the cleanup on an error or interrupt are the same.
    say : callable, optional
        Called with one line naming the user's files a rerun kept (module notes; default: a
        "note:" line on stderr).

    Yields
    ------
    Path
        The temporary folder to write into (a sibling of ``path``). Paths inside it become
        paths inside ``path`` after the block (:func:`rebase`).

    Raises
    ------
    OutputError
        ``path`` is below a file, not writable, holds files pim did not write (and no
        marker), holds a file pim wrote that was changed since, or another run holds its
        lock; at the end, a file of the user's has the name of one the run wrote.
    """
    path = _target(path, option)
    fd = _lock(path, option)
    try:
        _sweep(path)
        if merge:
            if path.exists() and not path.is_dir():
                raise OutputError(f"{option} {path}: not a folder")
        else:
            _check_not_a_mount(path, option)
            _check_replaceable(path, option)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.pim-tmp-", dir=path.parent))
        try:
            yield tmp
            if signal_received() is not None:       # an interrupt that was swallowed
                raise KeyboardInterrupt
            os.chmod(tmp, 0o777 & ~_umask())
            kept = []
            if not merge:
                _write_marker(tmp, command)
                kept = _keep(path, tmp, option)
            with held_signals():
                (_merge_in if merge else _swap_in)(tmp, path)
            if kept:
                (say or _note)(f"{option} {path}: kept {_names(kept)} (pim did not write "
                               f"{'it' if len(kept) == 1 else 'them'})")
        except OSError as exc:
            with held_signals():
                shutil.rmtree(tmp, ignore_errors=True)
            failure = _write_failure(exc, option, path, tmp)
            if failure is None:
                raise
            raise failure from exc
        except BaseException:
            with held_signals():
                shutil.rmtree(tmp, ignore_errors=True)
            raise
    finally:
        _unlock(path, fd)


def _write_failure(exc: OSError, option: str, path: Path, tmp: Path) -> OutputError | None:
    """An OSError while a run was written or swapped in, as an :class:`OutputError` naming
    the output folder and, where known, the file (its name inside the folder, not the
    temporary one); None for an OSError about a file outside the folder (an input), which
    stays as it is."""
    name = Path(exc.filename) if exc.filename else None
    if name is not None:
        for root in (tmp, path):
            with contextlib.suppress(ValueError):
                name = path / Path(os.path.abspath(name)).relative_to(root)
                break
        else:
            return None
    what = f"cannot write {name}" if name is not None and name != path else "cannot write"
    return OutputError(f"{option} {path}: {what} ({exc.strerror or exc}); nothing was "
                       f"written (an earlier run there is as it was)")


def _note(line: str) -> None:
    sys.stderr.write(f"note: {line}\n")
    sys.stderr.flush()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def rebase(paths: Iterable, tmp, folder) -> list[Path]:
    """Paths written inside ``tmp`` as they are after the swap: inside ``folder``."""
    tmp, folder = Path(tmp), Path(folder)
    return [folder / Path(p).relative_to(tmp) for p in paths]
