"""The table of docs/event.md is what the code gives (comparisons.docs.event)."""

from pathlib import Path

import pytest

from comparisons.docs import event as D
from comparisons.docs import event_staged as S
from comparisons.docs.__main__ import main
from pim.model.tyres import STANDARD_GRAVITY

DOCS = Path(__file__).resolve().parents[3] / "docs"


def test_the_committed_page_holds_the_table_the_code_gives():
    assert D.block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_slide_row_agrees_with_the_hand_value():
    table = D.impact_table()
    rows = {(r[0], r[1]): r for r in table.rows}
    slide = rows[("barrier slide, tyres 0.7", "rest")][3]
    hand = 25.0 / (2 * 0.7 * STANDARD_GRAVITY)
    assert slide.startswith(f"({-hand:.2f}, 0.00)")
    assert rows[("side slap, tyres 0.7", 2)][5] == "brach-capped"


@pytest.mark.slow
def test_the_committed_page_holds_the_monte_carlo_the_code_gives():
    """The Monte Carlo through the event's table (a reconstruction of 200 samples, its
    single-impact counterpart and 30 draws fitted both ways: about 10 s on idle cores, a
    minute and more on busy ones), and what it shows: the true speeds inside the 5-95 %
    through the event, outside the single-impact samples'."""
    table = D.monte_carlo_table()
    assert D.monte_carlo_block(table) in (DOCS / D.PAGE).read_text(encoding="utf-8")
    for row in table.rows:
        true, low, high = (cell.value for cell in (row[1], row[6], row[8]))
        assert not low < true < high, row[0]
    for row in table.rows:
        true, low, high = (cell.value for cell in (row[1], row[3], row[5]))
        assert low < true < high, row[0]


def test_regeneration_rewrites_only_the_blocks(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(D, "monte_carlo_block",
                        lambda table=None: f"{D.MC_BEGIN}\n| mc |\n{D.MC_END}")
    page = tmp_path / D.PAGE
    page.write_text(f"prose before\n{D.BEGIN}\n| old |\n{D.END}\nmiddle\n"
                    f"{D.MC_BEGIN}\n| old |\n{D.MC_END}\nbetween\n{S.BEGIN}\nold\n"
                    f"{S.END}\nprose after\n")
    assert main(["event", "--docs", str(tmp_path)]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {page}"
    assert page.read_text() == (f"prose before\n{D.block()}\nmiddle\n"
                                f"{D.MC_BEGIN}\n| mc |\n{D.MC_END}\nbetween\n{S.block()}\n"
                                f"prose after\n")
    with pytest.raises(ValueError, match="markers"):
        page.write_text("no markers\n")
        D.regenerate(tmp_path)
