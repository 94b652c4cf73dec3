"""report.html of `pim compare` (issue 20, item 4): one self-contained file, every table, the
case's units, the assumptions table split to fit a screen -- and, in a real headless
Chromium (Debian's ``chromium`` + ``chromium-driver``, driven by selenium; `.ci/run`
installs them), the page loads without console errors, the video plays with its stated
duration, every image loads and the first screen shows the title and the results.

The browser tests skip, saying why, when Chromium or its driver is not installed.
"""

import re
import shutil
import subprocess
import tempfile
import time
from dataclasses import replace

import imageio_ffmpeg
import numpy as np
import pytest

import pim
from comparisons.report.compare import compare_case
from comparisons.report.compare_document import ASSUMPTION_GROUPS, compare_document
from comparisons.report.html import render_html
from pim.io.html import split_columns

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """ricsac9 (a US-units case) with the animation and the assumptions, no sweep."""
    out = tmp_path_factory.mktemp("html") / "ricsac9"
    rep = compare_case(pim.load_case("ricsac9"), out, speed_error=False, progress=False)
    return out, rep, (out / "report.html").read_text()


def _tables(text):
    return re.findall(r'<table id="table-([\w-]+)"', text)


def test_report_html_is_written_beside_report_md_and_listed(report):
    out, rep, text = report
    assert out / "report.html" in rep.files
    assert "[report.html](report.html)" in (out / "report.md").read_text()
    assert text.startswith("<!DOCTYPE html>")


def test_every_table_is_present_and_the_results_come_first(report):
    _, rep, text = report
    ids = _tables(text)
    assert ids[0] == "results"
    for name in rep.data.tables:
        assert name in ids or f"{name}-1" in ids, name
    assert re.findall(r'<section id="([\w-]+)"', text)[:4] == \
        ["results", "misfit", "coefficients", "inputs"]


def test_numbers_speak_the_case_files_units(report):
    _, _, text = report
    results = text.split('id="table-results"')[1].split("</table>")[0]
    assert "mph" in results and "ft lbf" in results and "deg/s" in results
    assert "ft/s" not in results and "m/s" not in results
    assumptions = "".join(re.findall(r'id="table-assumptions-\d".*?</table>', text, re.S))
    assert "C_eff x [ft]" in assumptions and "C_eff y [ft]" in assumptions
    assert "[m]" not in assumptions and "[m/s]" not in assumptions


def test_the_assumptions_table_is_split_into_parts_that_fit_a_screen(report):
    _, rep, text = report
    table = rep.data.tables["assumptions"]
    first = table.columns[0]                                   # "assumption relaxed"
    parts = split_columns(table.columns, ASSUMPTION_GROUPS, first)
    assert len(parts) >= 3 and all(cols[0] == first for _, cols in parts)
    assert max(len(cols) for _, cols in parts) <= 8
    shown = [c for _, cols in parts for c in cols[1:]]
    assert sorted(shown) == sorted(table.columns[1:])          # each column once
    assert "Other columns" not in [c for c, _ in parts]        # the groups name them all
    assert len(re.findall(r'id="table-assumptions-\d"', text)) == len(parts)


def test_text_is_escaped(report):
    out, rep, _ = report
    data = replace(rep.data, case=replace(rep.data.case, name="<script>alert(1)</script>"),
                   warnings=['mu > 1 & "odd" <b>'], case_path="a b<c>")
    text = render_html(compare_document(data), out)
    assert "<script" not in text and "<b>" not in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text
    assert "mu &gt; 1 &amp; &quot;odd&quot; &lt;b&gt;" in text


def test_no_external_resources_and_a_reasonable_size(report):
    out, _, text = report
    for url in re.findall(r'(?:src|href|poster)="([^"]*)"', text):
        assert url.startswith(("data:", "#")) or (out / url).exists(), url[:80]
    assert not re.search(r"https?://", text) and "<link" not in text and "url(" not in text
    mp4 = (out / "animation.mp4").stat().st_size
    pngs = sum(p.stat().st_size for p in (out / "plots").glob("*.png"))
    size = len(text.encode())
    assert size < 4 / 3 * (mp4 + pngs) * 1.15 + 400_000    # base64 and a still frame
    assert size < 5_000_000


def test_the_video_is_h264_yuv420p(report):
    """What Chromium and every other browser play (ffmpeg's own description)."""
    out, _, _ = report
    probe = subprocess.run([imageio_ffmpeg.get_ffmpeg_exe(), "-hide_banner", "-i",
                            str(out / "animation.mp4")], capture_output=True, text=True)
    line = next(x for x in probe.stderr.splitlines() if "Video:" in x)
    assert "h264" in line and "yuv420p" in line, line


# -- in a real browser ------------------------------------------------------------------

@pytest.fixture(scope="module")
def browser():
    """Headless Chromium through selenium and Debian's chromedriver (skips without)."""
    if CHROMIUM is None or CHROMEDRIVER is None:
        pytest.skip("Chromium is not installed (apt-get install chromium chromium-driver; "
                    ".ci/run does)")
    webdriver = pytest.importorskip("selenium.webdriver",
                                    reason="selenium is not installed (the test extra)")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    profile = tempfile.mkdtemp(prefix="pim-chromium-")
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic",
                "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-sync", "--mute-audio",
                f"--user-data-dir={profile}", "--window-size=1280,900"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_script_timeout(30)
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


@pytest.fixture(scope="module")
def page(browser, report):
    """report.html loaded; the browser's console messages while loading."""
    out = report[0]
    browser.get_log("browser")                     # drop anything from before
    browser.get((out / "report.html").as_uri())
    deadline = time.time() + 30
    while browser.execute_script("return document.readyState") != "complete":
        assert time.time() < deadline, "the page did not finish loading in 30 s"
        time.sleep(0.1)
    return browser, browser.get_log("browser")


def test_page_loads_without_console_errors(page):
    _, log = page
    assert [e for e in log if e["level"] in ("SEVERE", "WARNING")] == []


def test_the_video_plays_and_lasts_its_stated_duration(page, report):
    driver, _ = page
    info = report[1].animation
    state = driver.execute_async_script("""
        const done = arguments[arguments.length - 1];
        const v = document.querySelector('video');
        const go = () => { const d = v.duration; v.muted = true;
            v.play().then(() => setTimeout(() => done({duration: d, t: v.currentTime,
                stated: parseFloat(v.dataset.duration), error: v.error && v.error.code}), 800))
             .catch(e => done({error: String(e)})); };
        if (v.readyState >= 1) go(); else v.addEventListener('loadedmetadata', go);""")
    assert state.get("error") is None, state
    assert state["stated"] == pytest.approx(info.frames / info.fps, abs=1e-4)
    assert abs(state["duration"] - state["stated"]) <= 1 / info.fps, state
    assert state["t"] > 0.1, state


def test_every_image_loads(page):
    driver, _ = page
    images = driver.execute_script(
        "return [...document.images].map(i => [i.alt, i.complete, i.naturalWidth])")
    assert len(images) >= 6                     # the sheet's plots and the video's still
    assert all(done and width > 0 for _, done, width in images), images


def test_the_first_screen_shows_the_title_and_the_answer(page, report, tmp_path):
    """Issue 28: the top cards were epsilon, beta, mu, the simulator's error and the unit
    system; now the first card is vehicle 1's delta-V with its interval, the PDOFs follow,
    and every card of the answer is on the first screen."""
    driver, _ = page
    driver.execute_script("window.scrollTo(0, 0)")
    box = driver.execute_script("""
        const r = e => e.getBoundingClientRect();
        const h1 = document.querySelector('h1'), cards = document.querySelector('dl.facts');
        return {height: innerHeight, width: innerWidth, title: h1.textContent,
                h1: r(h1).bottom, cards_top: r(cards).top, cards: r(cards).bottom,
                cards_right: r(cards).right,
                labels: [...cards.querySelectorAll('dt')].map(e => e.textContent),
                first: cards.querySelector('dd').textContent}""")
    assert box["title"] == "ricsac9: reconstruction report"
    assert box["labels"][:4] == ["delta-V, vehicle 1", "delta-V, vehicle 2",
                                 "PDOF, vehicle 1", "PDOF, vehicle 2"], box
    assert "epsilon" not in box["labels"] and "pymunk against PIM" not in box["labels"]
    card = report[1].data.tables["results"].rows[0]           # |delta-V|, digits as shown
    value, unit, low, high = card[1], card[3], card[4], card[5]
    assert box["first"].startswith(f"{value} {unit}") and f"5-95 %: {low} to {high}" in \
        box["first"], box["first"]
    assert box["h1"] < box["cards_top"] < box["cards"] <= box["height"], box
    assert box["cards_right"] <= box["width"], box
    shot = tmp_path / "first-screen.png"
    assert driver.save_screenshot(str(shot))
    from PIL import Image

    image = np.asarray(Image.open(shot).convert("L"))
    assert image.shape[1] >= 1000 and image.shape[0] >= 600
    assert image.std() > 20 and len(np.unique(image)) > 50        # not a blank page


#: The smallest text a figure may show at page width [CSS px].
READABLE_PX = 9.0


def test_every_figure_is_shown_at_a_readable_size(page):
    """Issue 28: the six-panel velocities figure, two to a row in a 1280 px window, showed
    its legend at about 5 px. Each PNG states its smallest text in image pixels
    (data-text-px); shown at its displayed width that text must be at least READABLE_PX."""
    driver, _ = page
    shown = driver.execute_script("""
        return [...document.querySelectorAll('figure.plot img')].map(i => ({
            alt: i.alt, width: i.getBoundingClientRect().width, natural: i.naturalWidth,
            text: parseFloat(i.dataset.textPx)}))""")
    assert len(shown) >= 7 and any(f["alt"] == "velocities" for f in shown)
    for f in shown:
        assert f["text"] > 0, f
        assert f["text"] * f["width"] / f["natural"] >= READABLE_PX, f


def test_print_shows_a_still_frame_instead_of_the_video(page):
    driver, _ = page
    driver.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": "print"})
    try:
        shown = driver.execute_script("""
            const s = e => getComputedStyle(e);
            return {video: s(document.querySelector('video')).display,
                    still: s(document.querySelector('img.print-only')).display,
                    page: s(document.getElementById('inputs')).breakBefore,
                    background: s(document.body).backgroundColor}""")
    finally:
        driver.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": ""})
    assert shown == {"video": "none", "still": "block", "page": "page",
                     "background": "rgb(255, 255, 255)"}
