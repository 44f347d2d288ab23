"""The web page of ``drillfatigue serve`` in a real headless Chromium (Selenium): the
twin's sections with a model, the ledger's inventory view with a ledger.

The browser and its driver are the Debian packages ``chromium`` and
``chromium-driver`` (``make browser`` installs them; ``make test`` depends on
it). Without them this test fails and says how to install them: it never
skips.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pandas as pd
import pytest

from drillfatigue.service import ModelRegistry, create_app

from testkit.service_helpers import EXAMPLES, running_server, synthetic_model
from testkit.tiny_surrogate import train_tiny_surrogate

pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore::DeprecationWarning")]
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         "--disable-dev-shm-usage", "--window-size=1400,2100")


def _find(*names: str) -> str:
    for name in names:
        path = shutil.which(name) or (f"/usr/bin/{name}" if Path(f"/usr/bin/{name}").is_file()
                                      else None)
        if path:
            return path
    pytest.fail(f"{' or '.join(names)} not found: run `make browser` (apt-get install "
                "chromium chromium-driver)", pytrace=False)


@pytest.fixture()
def browser(tmp_path: Path):  # noqa: ANN201
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    opts = webdriver.ChromeOptions()
    opts.binary_location = _find("chromium", "chromium-browser")
    for flag in FLAGS:
        opts.add_argument(flag)
    opts.add_argument(f"--user-data-dir={tmp_path / 'chromium-profile'}")
    driver = webdriver.Chrome(service=Service(_find("chromedriver")), options=opts)
    try:
        yield driver
    finally:
        driver.quit()


def test_page_replays_a_log_and_maps_a_window(browser, tmp_path: Path) -> None:  # noqa: ANN001
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    synthetic_model().save(tmp_path / "model", export=False)
    n_components = len(pd.read_csv(EXAMPLES / "components.csv"))
    with running_server(create_app(ModelRegistry({"demo": tmp_path / "model"}))) as url:
        browser.get(url + "/")
        wait = WebDriverWait(browser, 60)
        # the model card fills the constants (domain centres) and the model list
        wait.until(lambda d: d.find_element(By.ID, "constants-text").get_attribute("value"))
        assert browser.find_element(By.ID, "model-select").get_attribute("value") == "demo"
        # no ledger opened: its section says so in one line, and how to open one
        wait.until(lambda d: d.find_element(By.ID, "ledger-summary").text.startswith(
            "ledger: this server opened no ledger (allowed: start it with drillfatigue serve "
            "--ledger"))
        # upload the log and the component list through the file inputs
        browser.find_element(By.ID, "log-file").send_keys(str(EXAMPLES / "operating_log.csv"))
        browser.find_element(By.ID, "components-file").send_keys(
            str(EXAMPLES / "components.csv"))
        wait.until(lambda d: d.find_element(By.ID, "log-text").get_attribute("value")
                   .startswith("time_s"))
        wait.until(lambda d: d.find_element(By.ID, "components-text").get_attribute("value")
                   .startswith("serial"))
        browser.find_element(By.ID, "replay-button").click()
        status = browser.find_element(By.ID, "status")
        wait.until(lambda d: "replayed" in status.text or "error" in status.text)
        assert status.text.startswith("replayed"), status.text
        # one drawn marker per component (all nine are in the hole for the whole log)
        points = browser.find_elements(By.CSS_SELECTOR, "#damage-plot .scatterlayer .point")
        assert len(points) == n_components
        plotted = browser.execute_script(
            "return document.getElementById('damage-plot').data"
            ".reduce((n, t) => n + t.x.length, 0)")
        assert plotted == n_components
        summary = browser.find_element(By.ID, "replay-summary").text
        assert summary.startswith(f"{n_components} locations over 2 h;"), summary
        rows = browser.find_elements(By.CSS_SELECTOR, "#damage-table tbody tr")
        assert len(rows) == min(8, n_components)
        # the window's axes start on the model's domain (rpm and WOB from the model card)
        card_rpm = browser.execute_script(
            "return [document.getElementById('x-start').value, "
            "document.getElementById('x-stop').value, document.getElementById('y-name').value]")
        assert card_rpm[2] == "wob_kN" and float(card_rpm[0]) < float(card_rpm[1])
        # operating window of the first component over a grid reaching past the training
        # ranges: heat map with hatched out-of-domain cells
        browser.execute_script("document.getElementById('x-start').value = 20;"
                               "document.getElementById('x-stop').value = 240;")
        browser.find_element(By.ID, "window-button").click()
        wait.until(lambda d: "window map ready" in status.text or "error" in status.text)
        assert status.text == "window map ready", status.text
        traces = browser.execute_script(
            "return document.getElementById('window-plot').data.map(t => [t.type, t.name])")
        assert traces[0][0] == "heatmap"
        # 20-240 rpm reaches past the synthetic training range: some cells are out of
        # domain, drawn hatched
        assert ["scatter", "outside training domain"] in traces
        browser.execute_script("window.scrollTo(0, 0)")
        shot = tmp_path / "web_page.png"
        assert browser.save_screenshot(str(shot))
        assert shot.stat().st_size > 20_000
        # the interactive API docs render from the shipped Swagger UI
        browser.get(url + "/docs")
        wait.until(lambda d: len(d.find_elements(By.CSS_SELECTOR, ".opblock")) >= 9)


def test_the_field_example_button_replays_every_tally_item(browser, tmp_path: Path
                                                           ) -> None:  # noqa: ANN001
    """One click loads data/examples/field (LAS log, tally, survey) and replays it with a
    model of params.yaml's inputs: the bit is listed as not covered, nothing is dropped."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    root = Path(__file__).resolve().parents[2]
    model = train_tiny_surrogate(root / "params.yaml", tmp_path / "model")
    with running_server(create_app(ModelRegistry({"pipeline": model}))) as url:
        browser.get(url + "/")
        wait = WebDriverWait(browser, 120)
        wait.until(lambda d: d.find_element(By.ID, "constants-text").get_attribute("value"))
        browser.find_element(By.ID, "example-button").click()
        status = browser.find_element(By.ID, "status")
        wait.until(lambda d: "replayed" in status.text or "error" in status.text)
        assert status.text.startswith("replayed"), status.text
        assert browser.find_element(By.ID, "log-text").get_attribute("value").startswith(
            "~VERSION")
        summary = browser.find_element(By.ID, "replay-summary").text
        assert "not covered: BIT-01" in summary, summary
        retire = browser.find_element(By.ID, "retire-table").text
        assert "not covered" in retire and "BIT-01" in retire


def _ledger_with_runs(tmp_path: Path) -> str:
    """A SQLite ledger of two runs of the same joints, re-racked between them, built by
    the ledger's own ingest (stand-in damage function), and one inspection."""
    from testkit.ledger_logs import STANDIN, make_log, write_tally

    from drillfatigue.ledger import (
        LogChunk,
        end_run,
        ingest_chunk,
        init_ledger,
        load_joint_tally,
        record_inspection,
        start_run,
    )
    from drillfatigue.ledger.ingest import split_rows

    db = str(tmp_path / "ledger.sqlite")
    led, _ = init_ledger(db)
    orders = [["B1", "DC1", "DC2", "DP1", "DP2", "DP3"], ["B1", "DC2", "DC1", "DP3", "DP1", "DP2"]]
    for k, order in enumerate(orders):
        run = f"R{k + 1}"
        start_run(led, run, "W-1", load_joint_tally(write_tally(tmp_path / f"{run}.csv", order)),
                  "python:" + STANDIN, STANDIN)
        log = make_log(120, seed=20 + k, t0=10_000.0 * k, step_s=60.0)
        log = log.rename(columns={"wob_kN": "wob_N"}).assign(wob_N=lambda d: d["wob_N"] * 1e3)
        for piece in split_rows(LogChunk(log, run), 40):
            ingest_chunk(led, run, piece)
        if k == 0:
            end_run(led, run)
    record_inspection(led, "DC1", "2026-03-20", "UT", "rp7g2", "class2", wall_m=0.02, od_m=0.17)
    led.dispose()
    return db


def _texts(browser, selector: str) -> list[str]:  # noqa: ANN001
    from selenium.webdriver.common.by import By

    return [e.text for e in browser.find_elements(By.CSS_SELECTOR, selector)]


def test_ledger_view_lists_joints_retire_lists_and_a_history(browser, tmp_path: Path
                                                              ) -> None:  # noqa: ANN001
    """A server for a ledger alone: the inventory by remaining life, the retire and inspect
    lists under rules typed into the page, and one joint's history over its two runs, each
    as the ledger's own functions answer."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.support.ui import WebDriverWait

    from drillfatigue.ledger import RetireRules, history, inventory, open_ledger, retire_lists

    led = open_ledger(_ledger_with_runs(tmp_path))
    inv = inventory(led)
    dp = float(inv.loc[inv["component_type"] == "drill_pipe", "damage"].max())
    # the most damaged drill pipe retires; the upper bounds of some others reach inspect_at
    rules = RetireRules(retire_at=0.999 * dp, inspect_at=0.5 * dp, reinspect_after=0.5 * dp,
                        downgraded_retire_at=0.3 * dp)
    lists = retire_lists(led, rules)
    want_retire = list(lists.loc[lists["action"] == "retire", "serial"])
    want_inspect = list(lists.loc[lists["action"] == "inspect", "serial"])
    assert want_retire and want_inspect
    h = history(led, "DP1")
    with running_server(create_app(None, ledger=led)) as url:
        browser.get(url + "/")
        wait = WebDriverWait(browser, 60)
        status = browser.find_element(By.ID, "status")
        wait.until(lambda d: status.text.startswith("ledger:") or "error" in status.text)
        assert status.text == f"ledger: {len(inv)} joints, 2 runs", status.text
        # no model served: the model's sections are hidden, the ledger's shown
        assert not browser.find_element(By.ID, "replay-section").is_displayed()
        assert browser.find_element(By.ID, "ledger-section").is_displayed()
        assert "SQLite ledger" in browser.find_element(By.ID, "ledger-summary").text
        assert _texts(browser, "#runs-table tbody td:first-child") == ["R1", "R2"]
        # the inventory: every joint, least remaining life first, as inventory() orders them
        serials = _texts(browser, "#inventory-table tbody td:first-child")
        assert serials == list(inv["serial"])
        plotted = browser.execute_script(
            "return document.getElementById('inventory-plot').data[0].x")
        assert plotted == list(inv.loc[inv["damage"].notna(), "serial"])
        # the rules typed in; the lists as retire_lists() gives them
        browser.execute_script(
            "const v = arguments[0];"
            "document.getElementById('rule-retire-at').value = v[0];"
            "document.getElementById('rule-inspect-at').value = v[1];"
            "document.getElementById('rule-reinspect-after').value = v[2];"
            "document.getElementById('rule-downgraded-retire-at').value = v[3];",
            [repr(rules.retire_at), repr(rules.inspect_at), repr(rules.reinspect_after),
             repr(rules.downgraded_retire_at)])
        browser.find_element(By.ID, "lists-button").click()
        wait.until(lambda d: status.text.startswith("lists:") or "error" in status.text)
        assert status.text == (f"lists: {len(want_retire)} to retire, {len(want_inspect)} "
                               "to inspect"), status.text
        assert _texts(browser, "#ledger-retire-table tbody td:first-child") == want_retire
        assert _texts(browser, "#ledger-inspect-table tbody td:first-child") == want_inspect
        # a click on a serial opens its history over both runs, at its position in each
        link = next(a for a in browser.find_elements(By.CSS_SELECTOR, "#inventory-table a.serial")
                    if a.text == "DP1")
        link.click()
        wait.until(lambda d: status.text.startswith("history of") or "error" in status.text)
        assert status.text == "history of DP1: 2 runs", status.text
        assert "R1 (W-1, position 4), R2 (W-1, position 5)" in browser.find_element(
            By.ID, "history-summary").text
        cells = browser.find_elements(By.CSS_SELECTOR, "#history-table tbody tr")
        assert len(cells) == len(h.runs)
        bars = browser.execute_script(
            "return document.getElementById('history-plot').data.map(t => [t.name, t.x, t.y])")
        for name, runs, damage in bars:
            want = h.runs[h.runs["location"] == name]
            assert runs == list(want["run"])
            assert damage == pytest.approx(list(want["damage"]), rel=1e-12)
        # field units: lengths in ft in the history's headings
        browser.execute_script("const s = document.getElementById('ledger-units');"
                               "s.value = 'field'; s.dispatchEvent(new Event('change'));")
        wait.until(lambda d: "(ft)" in d.find_element(By.ID, "history-table").text)
        browser.execute_script("document.getElementById('ledger-section').scrollIntoView()")
        shot = tmp_path / "ledger_view.png"
        assert browser.save_screenshot(str(shot)) and shot.stat().st_size > 20_000
    led.dispose()
