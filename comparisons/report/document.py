"""A report as typed data: a :class:`Document` of :class:`Section` s holding typed blocks.

Every command that writes a report (``pim compare`` under every impact law, ``pim
reconstruct``, ``pim validate``, ``pim hard-cases``, ``pim speed-error``, ``pim pulses``,
``pim validate-models``, ``pim assumptions``) builds one of these and hands it to the one
pipeline (:mod:`comparisons.report.render`: Markdown and CSV; :mod:`comparisons.report.html`:
one self-contained HTML page; :func:`comparisons.report.render.write_document` writes them).
A builder states *what* the report says (text, tables of raw values, figures and videos by
their file in the report's folder); the renderers alone decide how it is written, so no
Markdown table or HTML is built anywhere else.

Text in blocks may use Markdown's inline marks (`code` and **bold**), which every renderer
understands.
"""

from __future__ import annotations

from dataclasses import dataclass

from comparisons.report.tables import Table

__all__ = ["Paragraph", "Bullets", "Callout", "Card", "Cards", "Figure", "Video", "Code",
           "FileList", "Section", "Document", "Block"]


@dataclass(frozen=True)
class Paragraph:
    """A paragraph of text.

    Attributes
    ----------
    text : str
        The text (inline marks allowed).
    """

    text: str


@dataclass(frozen=True)
class Bullets:
    """A bulleted list.

    Attributes
    ----------
    items : tuple of str
        One text per bullet (inline marks allowed).
    """

    items: tuple[str, ...]


@dataclass(frozen=True)
class Callout:
    """A highlighted box: a warning the reader must not miss.

    Attributes
    ----------
    title : str
        Its heading ("Warnings", "Plausibility").
    items : tuple of str
        One text per point (inline marks allowed).
    """

    title: str
    items: tuple[str, ...]


@dataclass(frozen=True)
class Card:
    """One key figure: a label, its value and a note (its interval, its unit's meaning).

    Attributes
    ----------
    label : str
        What the figure is ("delta-V, vehicle 1").
    value : str
        The value with its unit, formatted ("28.0 ft/s").
    note : str
        A line under the value ("5-95 %: 24.8 to 31.3").
    """

    label: str
    value: str
    note: str = ""


@dataclass(frozen=True)
class Cards:
    """Key figures in a row of boxes (the answer a report leads with).

    Attributes
    ----------
    cards : tuple of Card
        The figures, most important first.
    """

    cards: tuple[Card, ...]


@dataclass(frozen=True)
class Figure:
    """An image file of the report's folder.

    Attributes
    ----------
    path : str
        The file, relative to the report's folder (``plots/velocities.png``).
    alt : str
        Text for a reader who cannot see it.
    caption : str
        Caption (inline marks allowed).
    """

    path: str
    alt: str
    caption: str = ""


@dataclass(frozen=True)
class Video:
    """A video file of the report's folder (H.264 MP4).

    Attributes
    ----------
    path : str
        The file, relative to the report's folder.
    caption : str
        Caption (inline marks allowed).
    frames : int or None
        Number of frames (None: read from the file where the page needs it).
    fps : float or None
        Frames per second (None: read from the file).
    size : tuple of int or None
        Width and height [px].
    still_at : float
        Where (fraction of the duration) the still frame a printout shows is taken.
    """

    path: str
    caption: str
    frames: int | None = None
    fps: float | None = None
    size: tuple[int, int] | None = None
    still_at: float = 0.5


@dataclass(frozen=True)
class Code:
    """A command or other literal text, shown as a block.

    Attributes
    ----------
    text : str
        The literal text.
    """

    text: str


@dataclass(frozen=True)
class FileList:
    """The files of the report's folder, each linked.

    Attributes
    ----------
    paths : tuple of str
        Paths relative to the report's folder.
    """

    paths: tuple[str, ...]


Block = Paragraph | Bullets | Callout | Cards | Figure | Video | Code | FileList | Table


@dataclass(frozen=True)
class Section:
    """A titled part of a report.

    Attributes
    ----------
    id : str
        Its anchor (unique in the document).
    title : str
        Its heading.
    blocks : tuple of Block
        Its content, in order.
    toc : str
        Its name in the table of contents ("" : the title).
    keep : bool
        A printout keeps it on the page of the section before (no page break).
    """

    id: str
    title: str
    blocks: tuple
    toc: str = ""
    keep: bool = False


@dataclass(frozen=True)
class Document:
    """A whole report.

    Attributes
    ----------
    title : str
        Its title.
    generator : str
        The command that wrote it ("pim compare").
    sections : tuple of Section
        Its sections, in order.
    subtitle : str
        A line under the title (inline marks allowed).
    name : str
        The stem of its files (``report`` -> report.md, report.html).
    """

    title: str
    generator: str
    sections: tuple[Section, ...]
    subtitle: str = ""
    name: str = "report"

    def blocks(self):
        """Every block of every section, in order."""
        for section in self.sections:
            yield from section.blocks

    def tables(self) -> list[Table]:
        """Every table, in order (each is written as ``NAME.csv``)."""
        return [b for b in self.blocks() if isinstance(b, Table)]

    def media(self) -> list[str]:
        """The figure and video files the document shows (relative paths)."""
        return [b.path for b in self.blocks() if isinstance(b, Figure | Video)]
