"""The operator page's tests (mirroring vc/ui): a served machine with the built-in PLC over Modbus
TCP on 127.0.0.1 (ephemeral ports, time-outs), and Debian's headless Chromium driven through
chromium-driver by selenium.  The helpers are in ui_served.py (a test imports them from there)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from ui_served import CHROMEDRIVER, CHROMIUM, Served, serve_with_page


@pytest.fixture
def served() -> Iterator[Served]:
    yield from serve_with_page()


@pytest.fixture
def browser():  # type: ignore[no-untyped-def]
    """Headless Chromium through its WebDriver (chromium-driver)."""
    assert CHROMIUM is not None and CHROMEDRIVER is not None, "chromium and chromium-driver are required here"
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--window-size=1400,1000"):
        options.add_argument(argument)
    driver = webdriver.Chrome(options=options, service=Service(CHROMEDRIVER))
    driver.set_page_load_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()
