"""The web page of ``drillfatigue serve`` in a real headless Chromium (Selenium).

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

from service_helpers import EXAMPLES, running_server, synthetic_model
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
