"""The typed report document (comparisons.report.document): the blocks a builder states,
the tables and media a document holds, in order."""

import dataclasses

import pytest

from comparisons.report.document import (
    Bullets,
    Card,
    Cards,
    Document,
    Figure,
    Paragraph,
    Section,
    Video,
)
from comparisons.report.tables import Table

T1 = Table("a", "A", ("x",), ((1.0,),))
T2 = Table("b", "B", ("x",), ((2.0,),))


def test_tables_and_media_in_document_order():
    doc = Document("t", "pim test", (
        Section("one", "One", (Paragraph("p"), T1, Figure("f.png", alt="f"))),
        Section("two", "Two", (Video("v.mp4", "c", 10, 5.0), T2, Bullets(("x",))))))
    assert doc.tables() == [T1, T2]
    assert doc.media() == ["f.png", "v.mp4"]
    assert [type(b).__name__ for b in doc.blocks()] == ["Paragraph", "Table", "Figure",
                                                        "Video", "Table", "Bullets"]
    assert doc.name == "report"


def test_blocks_are_immutable_values():
    card = Card("delta-V, vehicle 1", "28.0 ft/s", "5-95 %: 24.8 to 31.3")
    with pytest.raises(dataclasses.FrozenInstanceError):
        card.value = "x"
    assert Cards((card,)) == Cards((Card("delta-V, vehicle 1", "28.0 ft/s",
                                         "5-95 %: 24.8 to 31.3"),))
    assert Video("v.mp4", "c").frames is None           # read from the file when needed
