"""The web UI in a real headless Chromium (Selenium + the distribution's chromium-driver).

Loads the UI from a server on loopback, runs a search, opens a scenario, plays the animation and
checks what the canvas shows (the ego's and the key object's colours; frames differ), mines with a
program and sees the referred objects on the map, and checks that markup in a log id and a track id
is shown as text. Screenshots go to docs/screenshots/.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

SCREENSHOTS = Path(__file__).resolve().parents[2] / "docs" / "screenshots"
INSTALL = "apt-get install -y chromium chromium-driver"

# Pixels of one colour on the bird's-eye canvas (exact RGB match).
COUNT_COLOR_JS = """
const [r, g, b] = arguments[0];
const c = document.getElementById('bev');
const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
let n = 0;
for (let i = 0; i < d.length; i += 4) if (d[i] === r && d[i + 1] === g && d[i + 2] === b) n++;
return n;
"""
EGO_RGB = [0xD6, 0x27, 0x28]
KEY_RGB = [0xFF, 0x7F, 0x0E]
REF_RGB = [0x94, 0x67, 0xBD]


def _browser_paths() -> tuple[str, str]:
    browser = next(
        (p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None
    )
    driver = shutil.which("chromedriver")
    if browser is None or driver is None:
        pytest.skip(f"no headless Chromium and chromedriver found: {INSTALL}")
    return browser, driver


@pytest.fixture(scope="module")
def driver() -> Iterator[Any]:
    browser, chromedriver = _browser_paths()
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = browser
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--window-size=1400,1000",
    ):
        options.add_argument(arg)
    d = webdriver.Chrome(service=Service(executable_path=chromedriver), options=options)
    d.set_page_load_timeout(60)
    try:
        yield d
    finally:
        d.quit()


def _wait(predicate: Any, timeout_s: float = 30.0, what: str = "condition") -> Any:
    from selenium.common.exceptions import StaleElementReferenceException

    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            value = predicate()
        except StaleElementReferenceException:  # the UI re-rendered a table while it was read
            value = None
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def _count(d: Any, rgb: list[int]) -> int:
    n: int = d.execute_script(COUNT_COLOR_JS, rgb)
    return n


def _by_id(d: Any, element_id: str) -> Any:
    from selenium.webdriver.common.by import By

    return d.find_element(By.ID, element_id)


def _rows(d: Any, table_id: str) -> list[Any]:
    from selenium.webdriver.common.by import By

    rows: list[Any] = d.find_elements(By.CSS_SELECTOR, f"#{table_id} tbody tr")
    return rows


def test_search_open_play_and_mine(driver: Any, live: Any, hostile_ids: tuple[str, str]) -> None:
    from selenium.webdriver.support.ui import Select

    d = driver
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    d.get(live.url + "/")
    _wait(lambda: "logs" in _by_id(d, "store-summary").text, what="the store summary")
    _wait(lambda: _rows(d, "events-table"), what="the first search")
    # a search by category: every row shows that category
    options = [o.get_attribute("value") for o in Select(_by_id(d, "search-category")).options][1:]
    assert options, "the categories of the stored events are offered"
    Select(_by_id(d, "search-category")).select_by_value(options[0])
    _by_id(d, "search-button").click()
    _wait(lambda: _by_id(d, "search-status").text.endswith("event(s)"), what="search results")
    rows = _rows(d, "events-table")
    assert rows and all(r.find_elements("css selector", "td")[2].text == options[0] for r in rows)
    d.save_screenshot(str(SCREENSHOTS / "search.png"))

    # open the scenario: map, ego and key object drawn; the tags timeline and explanation shown
    rows[0].click()
    _wait(lambda: _by_id(d, "view-detail").is_displayed(), what="the detail view")
    _wait(lambda: _by_id(d, "bev").get_attribute("data-frame") == "0", what="the first frame")
    assert _count(d, EGO_RGB) > 20 and _count(d, KEY_RGB) > 20
    assert _by_id(d, "event-explanation").text.strip()
    assert len(d.find_elements("css selector", "#tags-timeline .tagrow")) >= 5
    first = d.execute_script("return document.getElementById('bev').toDataURL();")
    _by_id(d, "play-button").click()
    _wait(lambda: int(_by_id(d, "bev").get_attribute("data-frame")) >= 10, what="the animation to advance")
    _by_id(d, "play-button").click()  # pause
    frame = int(_by_id(d, "bev").get_attribute("data-frame"))
    time.sleep(0.5)
    assert int(_by_id(d, "bev").get_attribute("data-frame")) == frame, "paused means paused"
    assert d.execute_script("return document.getElementById('bev').toDataURL();") != first
    assert _count(d, EGO_RGB) > 20
    d.save_screenshot(str(SCREENSHOTS / "scenario.png"))
    # scrub back to the start: the first picture again
    d.execute_script(
        "const s = document.getElementById('scrub'); s.value = '0'; s.dispatchEvent(new Event('input'));"
    )
    assert d.execute_script("return document.getElementById('bev').toDataURL();") == first

    # mining: a program runs in the sandbox; its referred objects show on the map
    _by_id(d, "view-detail").find_element("id", "detail-back").click()
    d.find_element("css selector", "nav button[data-view=mining]").click()
    _by_id(d, "mine-description").send_keys("any vehicle")
    program = 'vehicles = get_objects_of_category(log_dir, category="VEHICLE")\n'
    program += "output_scenario(vehicles, description, log_dir, output_dir)"
    _by_id(d, "mine-program").send_keys(program)
    _by_id(d, "mine-button").click()
    _wait(lambda: _by_id(d, "mine-result").is_displayed(), timeout_s=90, what="the mining result")
    assert _by_id(d, "mine-program-shown").text.strip() == program
    assert "review" in _by_id(d, "mine-flags").text
    objects = _rows(d, "mine-objects")
    assert objects
    d.save_screenshot(str(SCREENSHOTS / "mining.png"))
    objects[0].click()
    _wait(lambda: _by_id(d, "view-detail").is_displayed(), what="the referred objects' log")
    _wait(lambda: _count(d, REF_RGB) > 20, what="referred objects drawn")
    d.save_screenshot(str(SCREENSHOTS / "mining-map.png"))


def test_hostile_names_are_shown_as_text(driver: Any, live: Any, hostile_ids: tuple[str, str]) -> None:
    log_id, track_id = hostile_ids
    d = driver
    d.get(live.url + "/")
    d.find_element("css selector", "nav button[data-view=logs]").click()
    _wait(lambda: len(_rows(d, "logs-table")) >= 4, what="the logs table")
    cells = [r.find_elements("css selector", "td")[0] for r in _rows(d, "logs-table")]
    hostile = [c for c in cells if c.text == log_id]
    assert hostile, "the hostile log id is shown literally"
    hostile[0].click()
    _wait(lambda: _by_id(d, "view-detail").is_displayed(), what="the hostile log's scene")
    _wait(lambda: track_id in _by_id(d, "track-list").text, what="the hostile track id as text")
    assert log_id in _by_id(d, "detail-title").text
    assert not d.find_elements("css selector", "main img, main b, main script")
    assert d.execute_script("return window.__pwned === undefined;")


def test_jobs_page_runs_analyze_and_reports_refusals(driver: Any, live: Any) -> None:
    d = driver
    d.get(live.url + "/")
    d.find_element("css selector", "nav button[data-view=jobs]").click()
    _by_id(d, "ingest-path").send_keys("/etc")
    _by_id(d, "ingest-form").find_element("css selector", "button").click()
    _wait(lambda: "outside" in _by_id(d, "error-bar").text, what="the refusal of a path outside the roots")
    _by_id(d, "analyze-form").find_element("css selector", "button").click()
    _wait(lambda: _by_id(d, "job-status").text.endswith("succeeded"), timeout_s=90, what="the analyze job")

    def analyze_succeeded() -> bool:
        cells = [[c.text for c in r.find_elements("css selector", "td")] for r in _rows(d, "jobs-table")]
        return any(c[1] == "analyze" and c[2] == "succeeded" for c in cells)

    _wait(analyze_succeeded, what="the finished job in the jobs table")
    rows = [[c.text for c in r.find_elements("css selector", "td")] for r in _rows(d, "jobs-table")]
    progress = next(c[3] for c in rows if c[1] == "analyze")
    assert progress and "0/0" not in progress  # an analyze with nothing left says so
    d.save_screenshot(str(SCREENSHOTS / "jobs.png"))
