"""The yaw dynamic index table of docs/inertia-estimate.md is what the code gives
(comparisons.docs.inertia_estimate), rendered by the one Markdown renderer."""

from pathlib import Path

import pytest

from comparisons.docs import inertia_estimate as D
from comparisons.docs.__main__ import main
from pim.io.inertia_data import dynamic_indices, held_out

DOCS = Path(__file__).resolve().parents[3] / "docs"


def test_the_committed_page_holds_the_table_the_code_gives():
    assert D.block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_table_is_typed_and_states_the_published_counts():
    table = D.index_table()
    car = dict(zip(table.columns, table.rows[0], strict=True))
    assert car["body"] == "car" and car["vehicles"] == 73       # Tse 2020: 73 cars
    assert car["mean D [-]"].value == pytest.approx(dynamic_indices()["car"].mean)
    inside, n, _ = held_out("car")
    assert car["held out: within 1.96 sd"] == inside
    assert car["held out: within [%]"].value == pytest.approx(100 * inside / n)
    assert sum(table.column("vehicles")) == 204


def test_regeneration_rewrites_only_the_block(tmp_path, capsys):
    page = tmp_path / D.PAGE
    page.write_text(f"prose before\n{D.BEGIN}\n| old | table |\n{D.END}\nprose between\n"
                    f"{D.MASS_BEGIN}\n| old |\n{D.MASS_END}\nmore prose\n"
                    f"{D.LENGTH_BEGIN}\n| old |\n{D.LENGTH_END}\nlength prose\n"
                    f"{D.AXLE_BEGIN}\n| old |\n{D.AXLE_END}\nprose after\n")
    assert main(["inertia-estimate", "--docs", str(tmp_path)]) == 0
    assert capsys.readouterr().out.strip() == f"wrote {page}"
    assert page.read_text() == (f"prose before\n{D.block()}\nprose between\n"
                                f"{D.mass_block()}\nmore prose\n"
                                f"{D.length_block()}\nlength prose\n"
                                f"{D.axle_block()}\nprose after\n")
    page.write_text("no markers\n")
    with pytest.raises(ValueError, match="markers"):
        D.regenerate(tmp_path)


def test_the_committed_page_holds_the_cg_position_table_the_code_gives():
    assert D.axle_block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_cg_position_table_is_typed_and_counts_the_52_vehicles():
    """NHTSA's NCAP 2004 table holds 52 vehicles (pim/io/data/nhtsa_ncap2004_cg_position.csv);
    the vans (3) take the pooled fraction of all 52."""
    table = D.axle_table()
    rows = {row[0]: dict(zip(table.columns, row, strict=True)) for row in table.rows}
    assert sum(table.column("vehicles")) == 52
    assert rows["van"]["a / L used"] == "all pooled" and rows["van"]["its vehicles"] == 52
    assert rows["car"]["a / L used"] == "its own"
    assert 0.35 < rows["car"]["mean a / L [-]"].value < rows["suv"]["mean a / L [-]"].value


def test_the_committed_page_holds_the_mass_line_table_the_code_gives():
    assert D.mass_block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_mass_line_table_states_the_published_lines():
    """Tse 2020's cars: I_z = 3.176 m - 1754.164, R^2 0.920, 73 vehicles; trucks: 131."""
    table = D.mass_table()
    rows = {row[0]: dict(zip(table.columns, row, strict=True)) for row in table.rows}
    assert rows["car"]["vehicles"] == 73 and rows["truck"]["vehicles"] == 131
    assert rows["car"]["slope [m^2]"].value == pytest.approx(3.176, abs=1e-3)
    assert rows["car"]["R^2 [-]"].value == pytest.approx(0.920, abs=5e-4)


def test_the_committed_page_holds_the_wheelbase_line_table_the_code_gives():
    assert D.length_block() in (DOCS / D.PAGE).read_text(encoding="utf-8")


def test_the_wheelbase_line_table_counts_lock_1993s_cars_and_vans():
    """Lock's 1993 data: 84 cars and 9 vans (R's table(MASS::Cars93$Type): 16 compact, 11
    large, 22 midsize, 21 small, 14 sporty, 9 van); the cars' line is used, the vans'
    (no significant slope) is not."""
    table = D.length_table()
    rows = {row[0]: dict(zip(table.columns, row, strict=True)) for row in table.rows}
    assert (rows["car"]["vehicles"], rows["van"]["vehicles"]) == (84, 9)
    assert (rows["car"]["used"], rows["van"]["used"]) == ("yes", "no")
    assert 0.3 < rows["car"]["slope [-]"].value < 0.5
