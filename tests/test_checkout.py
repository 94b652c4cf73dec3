"""The guard of tests/conftest.py (:mod:`tests.checkout`) sees what a run adds, and only that."""

from tests.checkout import gained, listing


def test_a_new_file_and_a_new_empty_folder_are_gained(tmp_path):
    (tmp_path / "pim").mkdir()
    (tmp_path / "pim" / "case.py").write_text("")
    before = listing(tmp_path)
    (tmp_path / "report.md").write_text("x")
    (tmp_path / "out" / "speed-error").mkdir(parents=True)
    (tmp_path / "out" / "speed-error" / "a.csv").write_text("1")
    (tmp_path / "empty").mkdir()
    assert gained(before, listing(tmp_path)) == ["empty/", "out/", "report.md"]


def test_caches_are_not_gained(tmp_path):
    before = listing(tmp_path)
    for cache in ("__pycache__", ".pytest_cache", ".hypothesis", "pim_harness.egg-info"):
        (tmp_path / "pim" / cache).mkdir(parents=True)
        (tmp_path / "pim" / cache / "x").write_text("")
    (tmp_path / "pim" / "m.pyc").write_text("")
    assert gained(before, listing(tmp_path)) == ["pim/"]     # the folder made here only


def test_a_file_in_an_existing_folder_is_gained_by_its_path(tmp_path):
    (tmp_path / "docs").mkdir()
    before = listing(tmp_path)
    (tmp_path / "docs" / "new.md").write_text("")
    assert gained(before, listing(tmp_path)) == ["docs/new.md"]
