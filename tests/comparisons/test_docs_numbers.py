"""The figures of docs/ are what the code gives: the committed documents against freshly
generated ones (comparisons.docs_numbers). The fast tests regenerate the pulses and the
ladder's verdicts (the verdicts-only study: the same contact times, tables and sentences
as the full one); the whole regeneration, sweeps and plots included, is slow."""

import csv
import io

import pytest

from comparisons import docs_numbers as D
from comparisons.report.assumptions import assumption_table, input_shift_table, verdicts
from comparisons.report.pulses import pulse_table, pulses_document
from comparisons.report.render import markdown_table, render_markdown, table_csv
from comparisons.studies.pulses import compare_pulses


@pytest.fixture(scope="module")
def verdict_study():
    return D.ricsac9_study(sweeps=False, executor="serial")


def _csv_rows(text: str) -> list:
    return list(csv.reader(io.StringIO(text)))


def _csv_drift(committed: str, generated: str) -> list:
    return D.drift("\n".join(",".join(r) for r in _csv_rows(committed)),
                   "\n".join(",".join(r) for r in _csv_rows(generated)))


def test_drift_finds_a_changed_number_or_text_and_passes_the_same():
    text = "PIM is 10.2 % off (delta-V 3.6 mph) at 100 ms"
    assert D.drift(text, text) == []
    assert D.drift(text, text.replace("10.2", "10.2000001")) == []        # round-off
    assert D.drift(text, text.replace("10.2", "12.9")) == ["10.2 is now 12.9"]
    assert D.drift(text, text.replace("mph", "km/h"))[0].startswith("the text differs")


def test_pulses_md_and_csv_hold_what_the_code_gives():
    c = compare_pulses()
    table = pulse_table(c)
    md = render_markdown(pulses_document(c, command="python -m comparisons.docs_numbers pulses"))
    assert D.drift((D.DOCS / "pulses.md").read_text(), md) == []
    assert _csv_drift((D.DOCS / "pulses-nhtsa10146.csv").read_text(), table_csv(table)) == []


def test_the_ladder_table_and_verdicts_in_docs_hold_what_the_code_gives(verdict_study):
    folder = D.DOCS / "assumptions-ricsac9"
    assert _csv_drift((folder / "assumptions.csv").read_text(),
                      table_csv(assumption_table(verdict_study))) == []
    assert _csv_drift((folder / "where_c.csv").read_text(),
                      table_csv(input_shift_table(verdict_study))) == []
    md = (folder / "assumptions.md").read_text()
    committed = md.split("## Verdicts\n\n", 1)[1].split("\n\n", 1)[0]
    assert D.drift(committed, "\n".join(f"- {v}" for v in verdicts(verdict_study))) == []


def test_the_contact_model_block_holds_what_the_code_gives(verdict_study):
    text = (D.DOCS / "contact-model.md").read_text()
    committed = D.BEGIN + text.split(D.BEGIN, 1)[1].split(D.END, 1)[0] + D.END
    assert D.drift(committed, D.contact_model_block(verdict_study)) == []


def test_the_fit_block_holds_what_the_code_gives():
    """docs/fit.md quotes pim fit's standard errors and pim sensitivity's sources (issue 33)
    as the commands print them."""
    text = (D.DOCS / "fit.md").read_text()
    committed = D.FIT_BEGIN + text.split(D.FIT_BEGIN, 1)[1].split(D.END, 1)[0] + D.END
    generated = D.fit_block()
    assert D.drift(committed, generated) == []
    assert "+- " in generated and "source" in generated


def test_the_contact_model_rungs_are_a_typed_table_rendered_by_the_renderer(verdict_study):
    """The block's table was built by hand (issue 27): now its rows hold the numbers [%]
    and the one Markdown renderer writes it."""
    table = D.rung_table(verdict_study)
    law = dict(zip(table.columns, table.rows[0], strict=True))
    assert law["rung"] == "law" and isinstance(law["marginal [%]"], float)
    assert law["marginal [%]"] == 100 * verdict_study.typical.rung("law").marginal
    assert markdown_table(table) in D.contact_model_block(verdict_study)


@pytest.mark.slow
def test_the_whole_regeneration_matches_the_committed_documents(tmp_path):
    study = D.ricsac9_study()
    D.assumptions_ricsac9(tmp_path, study=study)
    folder = D.DOCS / "assumptions-ricsac9"
    for name in ("assumptions.md", "assumptions.csv", "where_c.csv",
                 "assumption_sweeps.csv"):
        committed, generated = (folder / name).read_text(), (tmp_path / name).read_text()
        check = _csv_drift if name.endswith(".csv") else D.drift
        assert check(committed, generated) == [], name
    D.pulses(tmp_path)
    assert D.drift((D.DOCS / "pulses.md").read_text(), (tmp_path / "pulses.md").read_text()) \
        == []
    page = tmp_path / "contact-model.md"
    page.write_text(f"head\n{D.BEGIN}\nold\n{D.END}\ntail\n")
    D.contact_model(page, study=study)
    text = page.read_text()
    assert text.startswith("head\n") and text.endswith("\ntail\n")
    assert D.contact_model_block(study) in text
