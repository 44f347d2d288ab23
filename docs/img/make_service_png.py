"""Make ``docs/img/service.png``: the web page of ``drillfatigue serve`` after a replay.

Trains two small demonstration models (the synthetic table of
:func:`drillfatigue.surrogate.make_synthetic_dataset`, and one on the plan
query rows of the three case-2 profiles, as in ``tests/testkit/service_helpers.py``),
serves them on the loopback, and drives headless Chromium: upload the example
log and component list, replay, map the operating window of the second
component, rank the case-2 candidates with the plan model, screenshot.

Usage: ``python docs/img/make_service_png.py`` (needs chromium and chromedriver).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

from selenium import webdriver  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import Select, WebDriverWait  # noqa: E402
from service_helpers import EXAMPLES, PLAN, plan_model, running_server  # noqa: E402

from drillfatigue.config.surrogate import SurrogateConfig  # noqa: E402
from drillfatigue.service import ModelRegistry, create_app  # noqa: E402
from drillfatigue.surrogate import fit_surrogate, make_synthetic_dataset  # noqa: E402


def main() -> None:
    import yaml

    tmp = Path(tempfile.mkdtemp(prefix="service_png_"))
    cfg = SurrogateConfig(hidden_layers=(64, 64), max_epochs=80, patience=20, n_threads=2)
    fit_surrogate(make_synthetic_dataset(150, seed=1), cfg).save(tmp / "synthetic",
                                                                   export=False)
    plan_model().save(tmp / "plan_demo", export=False)
    reg = ModelRegistry({"synthetic": tmp / "synthetic", "plan_demo": tmp / "plan_demo"})
    opts = webdriver.ChromeOptions()
    opts.binary_location = "/usr/bin/chromium"
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--window-size=1400,1900",
                 f"--user-data-dir={tmp / 'profile'}"):
        opts.add_argument(flag)
    d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
    try:
        with running_server(create_app(reg)) as url:
            d.get(url + "/")
            wait = WebDriverWait(d, 120)
            status = d.find_element(By.ID, "status")
            wait.until(lambda d: d.find_element(By.ID, "constants-text").get_attribute("value"))
            # plan ranking with the plan model first, then the replay with the synthetic one
            Select(d.find_element(By.ID, "model-select")).select_by_value("plan_demo")
            wait.until(lambda d: "4 numeric" in d.find_element(By.ID, "model-info").text)
            text = yaml.safe_dump(PLAN, sort_keys=False)
            d.execute_script("document.getElementById('plan-text').value = arguments[0]", text)
            d.find_element(By.ID, "plan-button").click()
            wait.until(lambda d: "ranked" in status.text or "error" in status.text)
            Select(d.find_element(By.ID, "model-select")).select_by_value("synthetic")
            wait.until(lambda d: "13 numeric" in d.find_element(By.ID, "model-info").text)
            d.find_element(By.ID, "log-file").send_keys(str(EXAMPLES / "operating_log.csv"))
            d.find_element(By.ID, "components-file").send_keys(str(EXAMPLES / "components.csv"))
            wait.until(lambda d: d.find_element(By.ID, "log-text").get_attribute("value"))
            wait.until(lambda d: d.find_element(By.ID, "components-text").get_attribute("value"))
            d.find_element(By.ID, "replay-button").click()
            wait.until(lambda d: "replayed" in status.text or "error" in status.text)
            Select(d.find_element(By.ID, "window-component")).select_by_index(3)
            d.find_element(By.ID, "window-button").click()
            wait.until(lambda d: "window map" in status.text or "error" in status.text)
            d.execute_script("window.scrollTo(0, 0)")
            out = ROOT / "docs" / "img" / "service.png"
            d.save_screenshot(str(out))
            print(f"wrote {out}; status: {status.text}")
    finally:
        d.quit()


if __name__ == "__main__":
    main()
