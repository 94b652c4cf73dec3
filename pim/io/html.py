"""Self-contained HTML reports: a small set of building blocks every command's report uses.

A report is one ``.html`` file that opens offline and prints: figures are inlined as base64
PNG (``data:`` URIs), videos as base64 MP4 in a ``<video controls>`` element (H.264/yuv420p,
which every browser plays), the style sheet is inline and nothing is fetched from anywhere.
Every piece of text goes through :func:`esc` (``html.escape``), so a case name or a message
can never inject markup. The blocks return HTML strings: :func:`table`, :func:`figure`,
:func:`grid`, :func:`video`, :func:`section`, :func:`paragraph`, :func:`bullets`,
:func:`callout`, :func:`facts`, :func:`code`, :func:`links`, and :func:`page` assembles them
into a document with a header, a table of contents and a print style sheet (white
background, each section on a new page, a still frame in place of each video).

A figure is shown at its own pixel width, never wider, and narrower only where the page is
narrower than it; figures side by side wrap to the next line rather than shrink, so the
text in a figure keeps the size it was drawn at. A PNG written by
:func:`pim.io.files.save_figure` states the height of its smallest text [px]
(``TEXT_PX_KEY``), which :func:`figure` carries as ``data-text-px``: the browser test checks
the size that text is shown at.
"""

from __future__ import annotations

import base64
import html
import io
import re
from collections.abc import Iterable, Sequence
from pathlib import Path

import imageio.v2 as imageio

from .files import TEXT_PX_KEY

__all__ = ["esc", "inline", "data_uri", "table", "split_columns", "split_table", "figure",
           "grid", "video", "still_frame", "video_info", "section", "paragraph", "bullets",
           "callout", "facts", "code", "links", "page", "png_text_px", "HTML_REPORT_NAME",
           "TEXT_PX_KEY"]

#: File name of the HTML report beside report.md.
HTML_REPORT_NAME = "report.html"

_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^[—-]$")


def esc(text) -> str:
    """``text`` (any object, as ``str``) with ``& < > " '`` escaped."""
    return html.escape(str(text), quote=True)


def inline(text) -> str:
    """Escaped ``text`` with Markdown's inline marks rendered: `code`, **bold** and links to
    files beside the page, ``[text](path)`` (a relative path: no scheme, so no script)."""
    out = esc(text)
    out = re.sub(r"`([^`]+)`", r"<code>\1</code>", out)
    out = re.sub(r"\[([^\]\[]+)\]\(([\w.-][\w./-]*)\)", r'<a href="\2">\1</a>', out)
    return re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", out)


def data_uri(content: bytes, mime: str) -> str:
    """A ``data:`` URI of ``content`` (base64)."""
    return f"data:{mime};base64,{base64.b64encode(content).decode('ascii')}"


def _bytes(source) -> bytes:
    return source if isinstance(source, bytes | bytearray) else Path(source).read_bytes()


def table(columns: Sequence[str], rows: Iterable[Sequence[str]], *, title: str = "",
          note: str = "", numeric: Sequence[bool] | None = None, id: str = "",
          cls: str = "") -> str:
    """An HTML table of already formatted cells (escaped here).

    Parameters
    ----------
    columns : sequence of str
        Column headers (units in brackets).
    rows : iterable of sequence of str
        Formatted cells, one sequence per row.
    title : str
        Caption above the table.
    note : str
        A line under the caption (links and file names, Markdown inline marks allowed).
    numeric : sequence of bool, optional
        Right-align these columns (default: columns whose every non-empty cell is a number).
    id, cls : str
        The table's ``id`` and extra CSS class.
    """
    rows = [[str(c) for c in row] for row in rows]
    if numeric is None:
        numeric = [bool(cells) and all(_NUMBER.match(c.strip()) for c in cells)
                   for cells in ([r[i] for r in rows if r[i].strip()]
                                 for i in range(len(columns)))]
    align = [' class="num"' if n else "" for n in numeric]
    head = "".join(f"<th{a}>{esc(c)}</th>" for c, a in zip(columns, align, strict=True))
    body = "\n".join("<tr>" + "".join(f"<td{a}>{esc(c)}</td>"
                                      for c, a in zip(row, align, strict=True)) + "</tr>"
                     for row in rows)
    caption = ""
    if title or note:
        caption = (f"<caption>{esc(title)}"
                   + (f'<span class="note">{inline(note)}</span>' if note else "")
                   + "</caption>")
    ident = f' id="{esc(id)}"' if id else ""
    return (f'<div class="table-wrap"><table{ident} class="data {esc(cls)}">{caption}'
            f"<thead><tr>{head}</tr></thead>\n<tbody>\n{body}\n</tbody></table></div>")


def split_columns(columns: Sequence[str], groups, key: str) -> list[tuple[str, list[str]]]:
    """``columns`` in ``groups`` ((caption, names) pairs) that fit a screen, each group led
    by column ``key``; a name matches a header, or the header without its unit
    (``"fit rms"`` matches ``"fit rms [ft/s]"``); columns no group names form a last group,
    so none is lost."""
    def stem(c):
        return c.split(" [", 1)[0]

    used, parts = {key}, []
    for caption, names in groups:
        cols = [c for n in names for c in columns
                if c not in used and (c == n or stem(c) == n)]
        used.update(cols)
        if cols:
            parts.append((caption, [key] + cols))
    rest = [c for c in columns if c not in used]
    if rest:
        parts.append(("Other columns", [key] + rest))
    return parts


def split_table(columns: Sequence[str], rows: Sequence[Sequence[str]], groups, key: str, *,
                note: str = "", id: str = "") -> str:
    """A wide table as several tables one screen wide (:func:`split_columns`), one row per
    row of the original in each; their ids are ``id-1``, ``id-2``, ..."""
    columns = list(columns)
    parts = []
    for i, (caption, cols) in enumerate(split_columns(columns, groups, key), start=1):
        index = [columns.index(c) for c in cols]
        parts.append(table(cols, [[row[j] for j in index] for row in rows], title=caption,
                           note=note if i == 1 else "", id=f"{id}-{i}" if id else "",
                           cls="split"))
    return "\n".join(parts)


def png_text_px(content: bytes) -> tuple[int, int, float | None]:
    """Width and height [px] of a PNG and the height of its smallest text [px] when it
    states it (:data:`TEXT_PX_KEY`, written by :func:`pim.io.files.save_figure`)."""
    from PIL import Image

    with Image.open(io.BytesIO(content)) as im:
        text = im.info.get(TEXT_PX_KEY)
        return im.width, im.height, float(text) if text else None


def figure(image, *, alt: str, caption: str = "", mime: str = "image/png") -> str:
    """An inline image (``image``: bytes or a file path) with its caption, shown at most at
    its own pixel width (``max-width`` in CSS pixels), with ``data-text-px`` the height of
    its smallest text [image px] when the PNG states it."""
    content = _bytes(image)
    cap = f"<figcaption>{inline(caption)}</figcaption>" if caption else ""
    size = text = ""
    if mime == "image/png":
        width, height, px = png_text_px(content)
        size = f' width="{width}" height="{height}"'
        text = f' data-text-px="{px:.4g}"' if px else ""
    return (f'<figure class="plot"><img src="{data_uri(content, mime)}" '
            f'alt="{esc(alt)}"{size}{text} loading="eager">{cap}</figure>')


def grid(figures: Sequence[str]) -> str:
    """Figures side by side where the page is wide enough for them at their own width
    (they wrap to the next line rather than shrink)."""
    return '<div class="grid">' + "".join(figures) + "</div>"


def still_frame(mp4, at: float = 0.5) -> bytes:
    """A PNG of the frame at fraction ``at`` of the video ``mp4`` (a file path)."""
    from PIL import Image

    with imageio.get_reader(str(mp4), format="FFMPEG") as reader:
        n = reader.count_frames()
        frame = reader.get_data(min(max(int(at * n), 0), max(n - 1, 0)))
    buf = io.BytesIO()
    Image.fromarray(frame).save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def video_info(mp4) -> tuple[int, float, tuple[int, int]]:
    """Frames, frames per second and (width, height) [px] of the video file ``mp4``."""
    with imageio.get_reader(str(mp4), format="FFMPEG") as reader:
        meta = reader.get_meta_data()
        return reader.count_frames(), float(meta["fps"]), tuple(meta["size"])


def video(mp4, *, caption: str = "", frames: int | None = None, fps: float | None = None,
          size=None, still: bytes | None = None) -> str:
    """An inline MP4 (``mp4``: bytes or a file path; H.264/yuv420p) that plays in the page.

    ``frames`` and ``fps`` give its duration, stated in the caption and in the element's
    ``data-duration`` [s] (read from the file when not given, with its size); ``still``
    (PNG bytes) is the poster and what a printout shows.
    """
    if frames is None or fps is None:
        frames, fps, size = video_info(mp4)
    duration = frames / fps
    poster = f' poster="{data_uri(still, "image/png")}"' if still else ""
    dims = f' width="{int(size[0])}" height="{int(size[1])}"' if size else ""
    text = (f"{frames} frames at {fps:g} fps ({duration:.2f} s)"
            + (f", {size[0]} x {size[1]} px" if size else "") + ". " + caption)
    printed = (f'<img class="print-only" src="{data_uri(still, "image/png")}" '
               f'alt="a frame of the animation">' if still else "")
    return (f'<figure class="video"><video controls preload="auto" playsinline{dims}{poster} '
            f'data-duration="{duration:.6g}" data-frames="{frames}" data-fps="{fps:g}" '
            f'src="{data_uri(_bytes(mp4), "video/mp4")}">Your browser cannot play MP4 '
            f"video.</video>{printed}"
            f'<figcaption>{inline(text)}<span class="print-only"> (The video plays in the '
            f"HTML file; a printout shows the frame above.)</span></figcaption></figure>")


def paragraph(text: str) -> str:
    """A paragraph (escaped; `code` and **bold** rendered)."""
    return f"<p>{inline(text)}</p>"


def bullets(items: Iterable[str], cls: str = "") -> str:
    """A bulleted list (each item escaped; `code` and **bold** rendered)."""
    c = f' class="{esc(cls)}"' if cls else ""
    return f"<ul{c}>" + "".join(f"<li>{inline(i)}</li>" for i in items) + "</ul>"


def callout(title: str, items: Iterable[str]) -> str:
    """A highlighted box (a warning): its title and a bulleted list."""
    return f'<div class="warn"><strong>{esc(title)}</strong>{bullets(items)}</div>'


def code(text: str) -> str:
    """Literal text (a command) as a block."""
    return f"<pre><code>{esc(text)}</code></pre>"


def links(paths: Iterable[str]) -> str:
    """A list of links to files beside the page."""
    return '<ul class="files">' + "".join(
        f'<li><a href="{esc(p)}">{esc(p)}</a></li>' for p in paths) + "</ul>"


def facts(items: Iterable[tuple]) -> str:
    """Key figures as a row of labelled boxes: (label, value) or (label, value, note)."""
    def box(label, value, note=""):
        note = f' <span class="note">{inline(note)}</span>' if note else ""
        return f"<div><dt>{esc(label)}</dt><dd>{inline(value)}{note}</dd></div>"

    return '<dl class="facts">' + "".join(box(*item) for item in items) + "</dl>"


def section(title: str, body: str | Iterable[str], *, id: str, level: int = 2,
            cls: str = "") -> str:
    """A titled section (``body``: HTML, or pieces of HTML joined)."""
    if not isinstance(body, str):
        body = "\n".join(body)
    return (f'<section id="{esc(id)}" class="{esc(cls)}"><h{level}>{esc(title)}</h{level}>\n'
            f"{body}\n</section>")


def page(title: str, body: str | Iterable[str], *, subtitle: str = "",
         contents: Sequence[tuple[str, str]] = (), generator: str = "pim") -> str:
    """A whole HTML document: header, table of contents (``(id, title)`` pairs), body."""
    if not isinstance(body, str):
        body = "\n".join(body)
    toc = ""
    if contents:
        toc = ('<nav class="toc" aria-label="Contents">' + "".join(
            f'<a href="#{esc(i)}">{esc(t)}</a>' for i, t in contents) + "</nav>")
    sub = f'<p class="subtitle">{inline(subtitle)}</p>' if subtitle else ""
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f'<meta name="generator" content="{esc(generator)}">'
            f"<title>{esc(title)}</title><style>{CSS}</style></head>\n<body>"
            f'<header class="top"><h1>{esc(title)}</h1>{sub}{toc}</header>\n'
            f"<main>\n{body}\n</main></body></html>\n")


#: The style sheet: a light, print-friendly layout; tables scroll sideways on a narrow
#: screen rather than squeezing; print starts each section on a new page and shows still
#: frames instead of videos.
CSS = """
:root{--ink:#1d2733;--muted:#5b6775;--line:#d5dbe3;--head:#eef2f7;--accent:#1f5fa8;
--zebra:#f8fafc}
*{box-sizing:border-box}
html{-webkit-text-size-adjust:100%}
body{margin:0;background:#fff;color:var(--ink);
font:15px/1.5 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif}
header.top{padding:14px 32px 8px;border-bottom:3px solid var(--accent);background:#fff}
h1{font-size:1.55rem;margin:0 0 2px;line-height:1.25}
.subtitle{margin:0 0 6px;color:var(--muted);font-size:.92rem}
nav.toc{display:flex;flex-wrap:wrap;gap:2px 16px;font-size:.85rem}
nav.toc a{color:var(--accent);text-decoration:none}
nav.toc a:hover{text-decoration:underline}
main{padding:4px 32px 40px;max-width:1240px}
section{margin-top:18px}
h2{font-size:1.2rem;margin:14px 0 8px;padding-bottom:3px;border-bottom:1px solid var(--line)}
h3{font-size:1.02rem;margin:14px 0 6px}
p,ul{margin:6px 0;max-width:62rem}
ul{padding-left:1.3rem}
code{font:0.88em ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;background:#f1f3f6;
padding:0 3px;border-radius:3px}
.table-wrap{overflow-x:auto;margin:8px 0 14px;max-width:100%}
table.data{border-collapse:collapse;font-size:.86rem;font-variant-numeric:tabular-nums}
table.data caption{caption-side:top;text-align:left;font-weight:600;padding:0 0 4px;
white-space:nowrap}
table.data caption .note{font-weight:400;color:var(--muted);margin-left:8px}
table.data th,table.data td{border:1px solid var(--line);padding:3px 9px;vertical-align:top}
table.data th{background:var(--head);text-align:left;font-weight:600}
table.data td.num,table.data th.num{text-align:right;white-space:nowrap}
table.data tbody tr:nth-child(even){background:var(--zebra)}
table.split caption{font-size:.92rem}
.grid{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start}
.grid > *{flex:0 1 auto;min-width:0;max-width:100%}
figure{margin:8px 0 14px}
figure.plot img{display:block;max-width:100%;height:auto;border:1px solid var(--line);
background:#fff}
pre{background:#f1f3f6;padding:6px 10px;border-radius:3px;overflow-x:auto;max-width:62rem}
pre code{background:none;padding:0}
figure.video video{max-width:100%;height:auto;background:#000;border:1px solid var(--line)}
figcaption{font-size:.84rem;color:var(--muted);max-width:62rem}
dl.facts{display:flex;flex-wrap:wrap;gap:8px;margin:6px 0 10px}
dl.facts div{border:1px solid var(--line);border-left:3px solid var(--accent);
padding:3px 10px;background:#fbfcfe}
dl.facts dt{font-size:.72rem;color:var(--muted);text-transform:uppercase;letter-spacing:.03em}
dl.facts dd{margin:0;font-weight:600;font-size:.95rem}
dl.facts dd .note{font-weight:400;color:var(--muted);font-size:.82rem}
.warn{border-left:4px solid #c77700;background:#fff7e8;padding:4px 12px;margin:8px 0}
.print-only{display:none}
@media print{
@page{margin:14mm 12mm}
body{font-size:10.5pt;background:#fff;color:#000}
header.top{padding:0 0 6px;border-bottom:2px solid #000}
nav.toc{display:none}
main{padding:0;max-width:none}
section{break-before:page}
section.keep{break-before:auto}
h2,h3,caption{break-after:avoid}
table.data{font-size:8.5pt}
table.data caption{white-space:normal}
table.data tr,figure{break-inside:avoid}
.table-wrap{overflow:visible}
video{display:none!important}
.print-only{display:inline}
img.print-only{display:block;max-width:100%}
a{color:#000}
.grid{display:block}
}
"""
