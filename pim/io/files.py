"""Atomic file writing: an interrupted run never leaves a half-written file behind.

Every file the project writes (figures, reports, tables, animations) goes through
:func:`atomic_path`: the content is written to a temporary file in the same directory, which
is then renamed onto the target (``os.replace`` is atomic on one file system). On any error,
or KeyboardInterrupt, the temporary file is removed and the target is left as it was.
Before the rename the written file is checked (:func:`check_complete`): an MP4 whose encoder
failed to write its trailer (a full disk), a cut GIF or PNG is an error, never a file under
the final name. Whole output folders are transactions of their own (:mod:`pim.io.output`).
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path

from ..model.numbers import InputError

__all__ = ["atomic_path", "atomic_paths", "write_text", "save_figure", "writable_folder",
           "check_complete", "smallest_text_points", "TEXT_PX_KEY"]

#: PNG text key of :func:`save_figure`: the height of the figure's smallest text [image px]
#: (what a report checks its figures' readability with, :mod:`pim.io.html`).
TEXT_PX_KEY = "pim:smallest-text-px"


@contextlib.contextmanager
def atomic_paths(*paths) -> Iterator[tuple[Path, ...]]:
    """Yield temporary paths next to ``paths``; on success rename every one onto its path.

    Several files that belong together (an animation's MP4 and its GIF) are written as a set:
    each temporary file keeps its target's suffix (writers such as imageio pick the format
    from it), every one is checked (:func:`check_complete`) before the first rename, and on
    any error, or KeyboardInterrupt, all temporary files are removed and no target is
    touched. The final files get the usual permissions (0666 less the umask).
    """
    paths = [Path(p) for p in paths]
    temps: list[Path] = []
    try:
        for path in paths:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}-", suffix=f".tmp{path.suffix}",
                                       dir=path.parent)
            os.close(fd)
            temps.append(Path(tmp))
        try:
            yield tuple(temps)
            for tmp, path in zip(temps, paths, strict=True):
                check_complete(tmp, path)
            mask = os.umask(0)
            os.umask(mask)
            for tmp, path in zip(temps, paths, strict=True):
                os.chmod(tmp, 0o666 & ~mask)
                os.replace(tmp, path)
        except OSError as exc:
            named = _named(exc, temps, paths)
            if named is exc:
                raise
            raise named from exc
    finally:
        for tmp in temps:
            if tmp.exists():
                tmp.unlink()


def _named(exc: OSError, temps: list, paths: list) -> OSError:
    """``exc`` naming the file it failed to write as the user knows it: a temporary file's
    target, or with no file name (a full disk on a write) the targets; ``exc`` itself when
    it names another file."""
    name = exc.filename
    if name is not None and Path(name) not in temps:
        return exc
    where = (str(paths[temps.index(Path(name))]) if name is not None
             else ", ".join(map(str, paths)))
    return OSError(exc.errno, exc.strerror or str(exc), where)


@contextlib.contextmanager
def atomic_path(path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success rename it onto ``path``
    (:func:`atomic_paths` of one file)."""
    with atomic_paths(path) as (tmp,):
        yield tmp


def _mp4_boxes(data: bytes) -> list[bytes] | None:
    """Top-level box types of an MP4 file, or None when the boxes do not add up to the file."""
    types, at = [], 0
    while at < len(data):
        if len(data) - at < 8:
            return None
        size = int.from_bytes(data[at:at + 4], "big")
        header = 8
        if size == 1:
            if len(data) - at < 16:
                return None
            size, header = int.from_bytes(data[at + 8:at + 16], "big"), 16
        elif size == 0:
            size = len(data) - at
        if size < header or at + size > len(data):
            return None
        types.append(data[at + 4:at + 8])
        at += size
    return types


def check_complete(tmp, path=None) -> None:
    """Raise OSError when the written file ``tmp`` is cut short (checked by ``path``'s suffix).

    MP4: the top-level boxes add up to the file and include ``moov`` and ``mdat`` (ffmpeg
    writes ``moov`` in the trailer: a failed trailer leaves none). GIF: ends with the trailer
    byte 0x3B. PNG: ends with the IEND chunk. Other suffixes are not checked.
    """
    tmp = Path(tmp)
    suffix = Path(path if path is not None else tmp).suffix.lower()
    if suffix not in (".mp4", ".gif", ".png"):
        return
    data = tmp.read_bytes()
    if suffix == ".mp4":
        boxes = _mp4_boxes(data)
        ok = bool(data) and boxes is not None and b"moov" in boxes and b"mdat" in boxes
    elif suffix == ".gif":
        ok = data[:4] == b"GIF8" and data[-1:] == b";"
    else:
        ok = data[:8] == b"\x89PNG\r\n\x1a\n" and data[-12:-8] == b"\0\0\0\0" \
            and data[-8:-4] == b"IEND"
    if not ok:
        raise OSError(errno.EIO, f"the {suffix[1:].upper()} writer left an incomplete file "
                                 "(disk full or encoder failed); nothing written",
                      str(path if path is not None else tmp))


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically; return the path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


def smallest_text_points(fig) -> float | None:
    """The font size of the smallest visible, non-empty text of a matplotlib figure
    [points], or None when it has no text."""
    from matplotlib.text import Text

    sizes = [t.get_fontsize() for t in fig.findobj(Text)
             if t.get_visible() and t.get_text().strip()]
    return min(sizes) if sizes else None


def save_figure(fig, path, **savefig_kwargs) -> Path:
    """Write a matplotlib figure to ``path`` atomically; the suffix names the format.

    PNGs default to 120 dpi and state the height of their smallest text in image pixels
    under :data:`TEXT_PX_KEY` (font size [pt] x dpi / 72); figures without a layout engine
    get a tight bounding box; other keyword arguments go to ``Figure.savefig``.
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
    points = smallest_text_points(fig) if fmt == "png" else None
    if points is not None:
        dpi = options.get("dpi", fig.dpi)
        metadata = dict(options.get("metadata") or {})
        metadata[TEXT_PX_KEY] = f"{points * float(dpi) / 72:.4g}"
        options["metadata"] = metadata
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
