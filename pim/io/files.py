"""Atomic file writing: an interrupted run never leaves a half-written file behind.

Every file the project writes (figures, reports, tables, animations) goes through
:func:`atomic_path`: the content is written to a temporary file in the same directory, which
is then renamed onto the target (``os.replace`` is atomic on one file system). On any error,
or KeyboardInterrupt, the temporary file is removed and the target is left as it was.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

from ..model.numbers import InputError

__all__ = ["atomic_path", "write_text", "save_figure", "writable_folder"]


@contextlib.contextmanager
def atomic_path(path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``.

    The temporary file keeps ``path``'s suffix (writers such as imageio pick the format from
    it); the final file gets the usual permissions (0666 less the umask).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=f".tmp{path.suffix}",
                               dir=path.parent)
    os.close(fd)
    tmp = Path(tmp)
    try:
        yield tmp
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; return the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def save_figure(fig, path, **savefig_kwargs) -> Path:
    """Write a matplotlib figure to ``path`` atomically; the suffix names the format.

    PNGs default to 120 dpi; figures without a layout engine get a tight bounding box; other
    keyword arguments go to ``Figure.savefig``.
    """
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if not fmt:
        raise InputError(f"path {path} needs a suffix naming the format (.png, .svg)")
    supported = fig.canvas.get_supported_filetypes()
    if fmt not in supported:
        raise InputError(f"path {path}: .{fmt} is no image format matplotlib writes "
                         f"(use one of {', '.join('.' + k for k in sorted(supported))})")
    # A figure with a layout engine (constrained layout) already fits its labels: a tight
    # bounding box would only draw it a second time.
    tight = {} if fig.get_layout_engine() is not None else {"bbox_inches": "tight"}
    options = {**tight, **({"dpi": 120} if fmt == "png" else {}), **savefig_kwargs}
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, **options)
    return path


def writable_folder(path, option: str = "--out") -> Path:
    """Create folder ``path`` if needed and check that files can be written in it.

    Raises
    ------
    ValueError
        ``path`` or one of its parents is a regular file, or the folder cannot be created
        or written (read-only); the message names ``option`` and the path.
    """
    path = Path(path)
    for parent in [path, *path.parents]:
        if parent.exists() and not parent.is_dir():
            raise InputError(f"{option} {path}: {parent} is a file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot create the folder ({exc.strerror})") \
            from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(f"{option} {path}: the folder is not writable")
    return path
