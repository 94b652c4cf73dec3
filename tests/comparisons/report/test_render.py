"""The one report pipeline's renderers on hand-built typed documents (no simulation): the
Markdown and CSV renderers (comparisons.report.render), the HTML renderer
(comparisons.report.html). Every block type is
rendered by each; tables keep full precision in the CSV and the digits each cell states in
the page. The writer is tested in test_write.py."""

import math
import re

import pytest
from matplotlib.figure import Figure as MplFigure

from comparisons.report.document import (
    Bullets,
    Callout,
    Card,
    Cards,
    Code,
    Document,
    Figure,
    FileList,
    Paragraph,
    Section,
)
from comparisons.report.html import render_html
from comparisons.report.render import markdown_table, render_csv, render_markdown, table_csv
from comparisons.report.tables import Num, Table
from pim.io.files import save_figure

TABLE = Table("results", "Results", ("quantity", "value [m/s]", "ok", "note"),
              (("a | b", Num(28.0467, 1), True, None),
               ("c", 1234567.891, False, "x"),
               ("d", math.nan, None, "")))
WIDE = Table("wide", "Wide", ("key", "a [m]", "b", "c"), (("r1", 1.0, 2.0, 3.0),),
             groups=(("A and b", ("a", "b")),))
HIDDEN = Table("every_run", "Every run", ("x",), ((0.1,),), show=False)


@pytest.fixture
def doc():
    return Document("case <1>: report", "pim test", (
        Section("results", "Results", (
            Cards((Card("delta-V, vehicle 1", "28.0 ft/s", "5-95 %: 24.8 to 31.3"),)),
            Callout("Warnings", ("the fit is <poor>",)), TABLE, HIDDEN,
            Bullets(("one", "**two**")), Paragraph("see [results.csv](results.csv)")),
            keep=True),
        Section("plots", "Plots", (Figure("p.png", alt="a plot"), Figure("q.png", alt="q"),
                                   WIDE, Code("pim compare 'my case.toml'"),
                                   FileList(("p.png", "results.csv"))), toc="P")),
        subtitle="Written by `pim test`.")


@pytest.fixture
def folder(tmp_path):
    for name in ("p.png", "q.png"):
        fig = MplFigure(figsize=(2, 1))
        fig.subplots().set_title("t", fontsize=8)
        save_figure(fig, tmp_path / name)
    return tmp_path


def test_markdown_has_every_block_in_order(doc):
    text = render_markdown(doc)
    assert [line for line in text.splitlines() if line.startswith("#")] == \
        ["# case <1>: report", "## Results", "## Plots"]
    assert text.index("**delta-V, vehicle 1: 28.0 ft/s** (5-95 %: 24.8 to 31.3)") < \
        text.index("**Warnings:**") < text.index("**Results** ([results.csv](results.csv))")
    assert "- **two**" in text and "![a plot](p.png)" in text
    assert "```\npim compare 'my case.toml'\n```" in text and "- [p.png](p.png)" in text
    assert "Every run" not in text                     # a CSV-only table is not shown


def test_markdown_table_escapes_and_aligns_and_keeps_stated_digits():
    lines = markdown_table(TABLE).splitlines()
    assert lines[0] == "| quantity | value [m/s] | ok | note |"
    assert lines[1] == "|:---|---:|:---|:---|"
    assert lines[2] == "| a \\| b | 28.0 | yes |  |"
    assert lines[3] == "| c | 1.235e+06 | no | x |"
    assert lines[4] == "| d |  |  |  |"


def test_csv_keeps_full_precision(doc):
    files = render_csv(doc)
    assert list(files) == ["results.csv", "every_run.csv", "wide.csv"]
    assert table_csv(TABLE).splitlines() == [
        "quantity,value [m/s],ok,note", "a | b,28.0467,yes,", "c,1234567.891,no,x", "d,,,"]


def test_html_renders_every_block_escaped(doc, folder):
    page = render_html(doc, folder)
    assert "<script" not in page and "case &lt;1&gt;: report" in page
    assert page.index('class="facts"') < page.index('class="warn"') < \
        page.index('id="table-results"')
    assert "the fit is &lt;poor&gt;" in page and "<strong>two</strong>" in page
    assert '<a href="results.csv">results.csv</a>' in page
    assert page.count('<div class="grid">') == 1 and page.count("data:image/png") == 2
    assert re.findall(r'data-text-px="([\d.]+)"', page) == ["13.33", "13.33"]  # 8 pt, 120 dpi
    assert 'id="table-wide-1"' in page and 'id="table-wide-2"' in page   # the groups
    assert "<pre><code>pim compare &#x27;my case.toml&#x27;</code></pre>" in page
    assert 'id="table-every_run"' not in page
    assert '<a href="#plots">P</a>' in page and '<section id="results" class="keep">' in page


def test_an_unknown_block_is_refused(folder):
    bad = Document("t", "pim test", (Section("s", "S", ("a bare string",)),))
    with pytest.raises(TypeError):
        render_markdown(bad)
    with pytest.raises(TypeError):
        render_html(bad, folder)
