"""The tables of docs/event.md are what the code gives (comparisons.docs.event), and the
energy figures' claims hold."""

from pathlib import Path

import pytest

from comparisons.docs import event as D
from comparisons.docs import event_staged as S
from comparisons.docs.__main__ import main
from pim.model.tyres import STANDARD_GRAVITY

DOCS = Path(__file__).resolve().parents[3] / "docs"


def test_the_committed_page_holds_the_table_the_code_gives():
    assert D.block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_committed_page_holds_the_energy_table_the_code_gives():
    assert D.energy_block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_a_further_impact_gains_energy_only_where_its_sticking_impulse_pulls():
    """The page's claim on a sample of the generated side slaps: none is refused for energy,
    some further impacts are solved frictionless (their capped answer gains energy), and
    each of those has a sticking impulse that pulls (Pn0 < 0)."""
    counts = D.energy_counts(D.generated_side_slaps(40, seed=1))
    assert counts["energy"] == 0
    assert counts["frictionless"] > 0 and counts["pulling"] == counts["frictionless"]


def test_the_slide_row_agrees_with_the_hand_value():
    table = D.impact_table()
    rows = {(r[0], r[1]): r for r in table.rows}
    slide = rows[("barrier slide, tyres 0.7", "rest")][3]
    hand = 25.0 / (2 * 0.7 * STANDARD_GRAVITY)
    assert slide.startswith(f"({-hand:.2f}, 0.00)")
    assert rows[("side slap, tyres 0.7", 2)][5] == "brach-capped"


def test_the_committed_page_holds_the_monte_carlo_the_code_gives():
    """The Monte Carlo through the event's table (a reconstruction of 200 samples, its
    single-impact counterpart and 30 draws fitted both ways: the suite's slower tests), and
    what it shows: the true speeds inside the 5-95 % through the event, outside the
    single-impact samples'."""
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
    page.write_text(f"prose before\n{D.BEGIN}\n| old |\n{D.END}\nbetween\n"
                    f"{D.ENERGY_BEGIN}\n| old |\n{D.ENERGY_END}\nand\n{S.BEGIN}\nold\n"
                    f"{S.END}\nthen\n{D.MC_BEGIN}\n| old |\n{D.MC_END}\nprose after\n")
    assert main(["event", "--docs", str(tmp_path)]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {page}"
    assert page.read_text() == (f"prose before\n{D.block()}\nbetween\n{D.energy_block()}"
                                f"\nand\n{S.block()}\nthen\n{D.MC_BEGIN}\n| mc |\n"
                                f"{D.MC_END}\nprose after\n")
    with pytest.raises(ValueError, match="markers"):
        page.write_text("no markers\n")
        D.regenerate(tmp_path)
