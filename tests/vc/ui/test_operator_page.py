"""The operator page in a real headless browser (Debian's Chromium through chromium-driver), against
``vc serve --realtime --ui`` with the built-in PLC over Modbus TCP: what a person at the machine does."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from ui_served import Served, needs_browser, serve_with_page

pytestmark = [needs_browser, pytest.mark.realtime, pytest.mark.timeout(240)]
WAIT_S = 20.0


def wait_until(check: Callable[[], object], what: str, timeout: float = WAIT_S) -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if check():
            return
        time.sleep(0.1)
    raise AssertionError(f"not within {timeout} s: {what}")


def shoot(browser, name: str) -> None:  # type: ignore[no-untyped-def]
    """The screenshots of docs/ui.md: VC_UI_SCREENSHOTS=docs/ui pytest tests/vc/ui/test_operator_page.py."""
    folder = os.environ.get("VC_UI_SCREENSHOTS")
    if folder:
        assert browser.save_screenshot(str(Path(folder) / f"{name}.png"))


def open_page(browser, served: Served):  # type: ignore[no-untyped-def]
    from selenium.webdriver.common.by import By

    browser.get(served.url)
    wait_until(lambda: browser.find_element(By.ID, "connection").text == "connected", "the page connects")
    wait_until(lambda: browser.find_elements(By.ID, "key-MCP.jog"), "the panel is built from the machine file")
    wait_until(lambda: browser.find_element(By.ID, "mode").text.startswith("mode "), "the first snapshot")
    # the PLC runs once it asks for JOG (basic_machine's mode after its start, DB11.DBX0.2)
    row = watch(browser, "DB11.DBX0.2")
    wait_until(lambda: row.find_element(By.CSS_SELECTOR, "td.value").text == "1", "the PLC runs", timeout=40)
    row.find_element(By.CSS_SELECTOR, "button.remove").click()
    return By


def press(browser, key: str, seconds: float = 0.15) -> None:  # type: ignore[no-untyped-def]
    """Press and hold a key of the panel with the mouse for ``seconds``, then let go."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By

    button = browser.find_element(By.ID, f"key-{key}")
    ActionChains(browser).click_and_hold(button).pause(seconds).release().perform()


def cell(browser, axis: str, quantity: str) -> str:  # type: ignore[no-untyped-def]
    from selenium.webdriver.common.by import By

    return str(browser.find_element(By.CSS_SELECTOR, f"#axis-{axis} .{quantity}").text)


def watch(browser, name: str):  # type: ignore[no-untyped-def]
    from selenium.webdriver.common.by import By

    browser.find_element(By.ID, "watch-name").send_keys(name)
    browser.find_element(By.CSS_SELECTOR, "#watch-add button").click()
    row = browser.find_element(By.CSS_SELECTOR, f'#watch-table tr[data-name="{name}"]')
    wait_until(lambda: row.find_elements(By.CSS_SELECTOR, "td")[2].text, f"{name} resolved in the watch table")
    return row


def messages(browser) -> str:  # type: ignore[no-untyped-def]
    from selenium.webdriver.common.by import By

    return str(browser.find_element(By.ID, "messages").text)


def test_jog_x1_moves_it_and_lights_the_traverse_command_in_the_watch_table(browser, served: Served) -> None:
    from selenium.webdriver.common.action_chains import ActionChains

    by = open_page(browser, served)
    row = watch(browser, "DB31.DBX64.7")
    assert row.find_elements(by.CSS_SELECTOR, "td")[1].text == "X1.basic.in.traversPlusCommandActive"
    if os.environ.get("VC_UI_SCREENSHOTS"):  # the screenshot shows a forced sensor too (it does not stop JOG)
        watch(browser, "X1.refCam").find_element(by.CSS_SELECTOR, "button.force").click()
    press(browser, "MCP.jog")
    wait_until(lambda: browser.find_element(by.ID, "mode").text == "mode JOG", "JOG mode")
    start = float(cell(browser, "X1", "position"))
    value = row.find_element(by.CSS_SELECTOR, "td.value")
    assert value.text == "0"
    button = browser.find_element(by.ID, "key-MCP.plus.X1")
    ActionChains(browser).click_and_hold(button).perform()
    try:
        wait_until(lambda: value.text == "1", "DB31.DBX64.7 = 1 while X1+ is held")
        assert "bit1" in str(value.get_attribute("class"))
        wait_until(lambda: float(cell(browser, "X1", "velocity")) > 0, "X1 moves in plus")
        shoot(browser, "operator_page")
    finally:
        ActionChains(browser).release().perform()
    wait_until(lambda: value.text == "0", "DB31.DBX64.7 = 0 once X1+ is let go")
    wait_until(lambda: float(cell(browser, "X1", "velocity")) == 0, "X1 stops")
    assert float(cell(browser, "X1", "position")) > start + 1


def test_reference_an_axis_from_the_panel(browser, served: Served) -> None:
    """JOG, REF, then hold Y1- (the inclined axis's Y1 is referenced first) until it is referenced."""
    from selenium.webdriver.common.action_chains import ActionChains

    by = open_page(browser, served)
    assert cell(browser, "Y1", "referenced") == "no"
    press(browser, "MCP.jog")
    press(browser, "MCP.ref")
    wait_until(lambda: browser.find_element(by.ID, "mode").text == "mode JOG REF", "the REF machine function")
    ActionChains(browser).click_and_hold(browser.find_element(by.ID, "key-MCP.minus.Y1")).perform()
    try:
        wait_until(lambda: cell(browser, "Y1", "referenced") == "yes", "Y1 referenced", timeout=40)
    finally:
        ActionChains(browser).release().perform()


def test_force_a_cam_see_it_forced_and_release_it(browser, served: Served) -> None:
    by = open_page(browser, served)
    cam = watch(browser, "X1.refCam")
    assert cam.find_elements(by.CSS_SELECTOR, "td")[2].text == "I7.0"
    reading = watch(browser, "DB31.DBX12.7")  # the PLC copies the cam to the NC (basic_machine network 4)
    value = cam.find_element(by.CSS_SELECTOR, "td.value")
    assert value.text == "0"
    cam.find_element(by.CSS_SELECTOR, "button.force").click()
    wait_until(lambda: value.text == "1" and "forced" in str(cam.get_attribute("class")), "the cam forced to 1")
    assert cam.find_element(by.CSS_SELECTOR, ".forced-mark").text.strip() == "F"
    wait_until(lambda: reading.find_element(by.CSS_SELECTOR, "td.value").text == "1", "the PLC passes it on")
    cam.find_element(by.CSS_SELECTOR, "button.release").click()
    wait_until(lambda: value.text == "0" and "forced" not in str(cam.get_attribute("class")), "released")
    wait_until(lambda: reading.find_element(by.CSS_SELECTOR, "td.value").text == "0", "the PLC sees the cam free")


def test_a_refused_force_is_shown(browser, served: Served) -> None:
    """A PLC-to-NC signal without --allow-writers, an NC-to-PLC signal: both refused, both said why."""
    by = open_page(browser, served)
    for name, reason in (("DB31.DBX4.7", "--allow-writers"), ("DB31.DBX64.7", "watched, not forced")):
        row = watch(browser, name)
        row.find_element(by.CSS_SELECTOR, "button.force").click()
        wait_until(lambda reason=reason: reason in messages(browser), f"the refusal of {name}")
        assert "forced" not in str(row.get_attribute("class"))
    watch_box = browser.find_element(by.ID, "watch-name")
    watch_box.send_keys("DB31.DBX999.9")
    browser.find_element(by.CSS_SELECTOR, "#watch-add button").click()
    wait_until(lambda: "DB31.DBX999.9" in messages(browser), "the unknown signal refused")


def test_emergency_stop_raises_its_alarm_and_reset_clears_it(browser, served: Served) -> None:
    by = open_page(browser, served)
    assert not browser.find_elements(by.ID, "alarm-3000")
    estop = browser.find_element(by.ID, "key-EStop.chainOk")
    estop.click()
    wait_until(lambda: browser.find_elements(by.ID, "alarm-3000"), "alarm 3000 shown")
    time.sleep(0.3)
    shoot(browser, "emergency_stop")
    alarm = browser.find_element(by.ID, "alarm-3000").text
    assert "Emergency stop" in alarm or "emergency stop" in alarm.lower()
    assert "on" in str(estop.get_attribute("class"))
    estop.click()  # pulled out again: the chain closes
    wait_until(lambda: "on" not in str(estop.get_attribute("class")).split(), "the e-stop released")
    press(browser, "MCP.reset", 0.3)
    wait_until(lambda: not browser.find_elements(by.ID, "alarm-3000"), "alarm 3000 cleared by RESET")


def test_mda_block_typed_and_started_needs_the_axes_referenced(browser, served: Served) -> None:
    """An MDA block typed into the page and started with NC START: on a machine not yet referenced the
    NC refuses the start with alarm 10203 (MD20700), which the page shows and RESET clears."""
    by = open_page(browser, served)
    press(browser, "MCP.mda")
    wait_until(lambda: browser.find_element(by.ID, "mode").text == "mode MDA", "MDA mode")
    browser.find_element(by.ID, "mda-text").send_keys("G91 G1 Z5 F2000")
    browser.find_element(by.ID, "mda-load").click()
    wait_until(lambda: "MDA program loaded into CHAN1" in messages(browser), "the program loaded")
    press(browser, "MCP.ncStart", 0.3)
    wait_until(lambda: browser.find_elements(by.ID, "alarm-10203"), "alarm 10203 shown")
    assert "NC start without reference point" in browser.find_element(by.ID, "alarm-10203").text
    assert cell(browser, "Z1", "position") == "0.000"
    press(browser, "MCP.reset", 0.3)
    wait_until(lambda: not browser.find_elements(by.ID, "alarm-10203"), "alarm 10203 cleared by RESET")


def test_the_plc_connection_is_shown_and_the_lost_sign_of_life_too(browser, served: Served) -> None:
    """The link, its session, the PLC peer and the pacing as vc serve --stats prints them; then the
    PLC process ends: the session closes and alarm 2000 (no sign of life for MD10100) appears."""
    import re

    by = open_page(browser, served)

    def shown(name: str) -> str:
        return str(browser.find_element(by.ID, f"plc-{name}").text)

    assert shown("link").startswith("Modbus TCP on 127.0.0.1:")
    assert shown("mode") == "real time"
    assert shown("session") == "1"
    wait_until(lambda: "PLC at 127.0.0.1" in shown("peer") and "requests" in shown("peer"), "the PLC peer")
    assert shown("life").startswith("ok")
    overruns = re.fullmatch(r"(\d+) of (\d+) cycles \((\d+) while serving the links\)", shown("overruns"))
    assert overruns is not None, shown("overruns")
    cycles = int(overruns[2])
    wait_until(lambda: int(shown("overruns").split(" of ")[1].split()[0]) > cycles, "the cycles counted on")
    shoot(browser, "plc_connection")
    assert served.plc is not None
    served.plc.terminate()
    served.plc.wait(10)
    wait_until(lambda: "alarm 2000" in shown("life"), "the lost sign of life (alarm 2000)")
    assert "lost" in str(browser.find_element(by.ID, "plc-life").get_attribute("class"))
    wait_until(lambda: browser.find_elements(by.ID, "alarm-2000"), "alarm 2000 in the alarm table")
    wait_until(lambda: "was lost" in shown("peer"), "the session closed")


@pytest.fixture
def served_recording(tmp_path: Path) -> Iterator[Served]:
    yield from serve_with_page("--record", str(tmp_path / "session.jsonl"))


def test_record_end_it_on_the_page_and_its_scenario_passes_vc_run(browser, served_recording: Served,
                                                                  tmp_path: Path) -> None:
    """vc serve --record: jog X1 from the page, end the recording there, download the scenario the
    page offers and run it with vc run (plc: none: the recorded PLC's writes are its steps)."""
    import subprocess
    import sys
    import urllib.request

    by = open_page(browser, served_recording)
    state = browser.find_element(by.ID, "record-state")
    wait_until(lambda: state.text.startswith(f"recording to {tmp_path / 'session.jsonl'}"), "recording shown")
    link = browser.find_element(by.ID, "record-scenario")
    assert not link.is_displayed()
    press(browser, "MCP.jog")
    wait_until(lambda: browser.find_element(by.ID, "mode").text == "mode JOG", "JOG mode")
    press(browser, "MCP.plus.X1", 0.5)
    wait_until(lambda: float(cell(browser, "X1", "velocity")) == 0 and float(cell(browser, "X1", "position")) > 0,
               "X1 jogged and stopped")
    browser.find_element(by.ID, "record-stop").click()
    wait_until(lambda: "has ended at cycle" in state.text and link.is_displayed(), "the recording ended")
    assert "its scenario can be downloaded" in messages(browser)
    assert browser.find_element(by.ID, "record-stop").get_attribute("disabled") is not None
    shoot(browser, "record")
    with urllib.request.urlopen(str(link.get_attribute("href")), timeout=30) as response:
        assert 'filename="session.yaml"' in response.headers["Content-Disposition"]
        text = response.read().decode("utf-8")
    scenario = tmp_path / "from_the_page.yaml"
    scenario.write_text(text, encoding="utf-8")
    assert "plc: none" in text
    run = subprocess.run([sys.executable, "-m", "vc.cli.main", "run", str(scenario)], capture_output=True, text=True,
                         timeout=180, cwd=Path(__file__).resolve().parents[3])
    assert run.returncode == 0, run.stdout + run.stderr


def test_scope_triggers_on_x1_key_saves_png_and_a_vcd_gtkwave_reads(browser, served: Served, tmp_path: Path) -> None:
    """Lanes X1's key (MCP.plus.X1), DB31.DBX64.7 and X1.position; trigger on the key rising; hold the
    key: the frozen diagram shows the key 0, 1 and 0 again; the PNG is the canvas, the VCD (written by
    the server from the samples it kept) is converted by GTKWave's vcd2fst and read by pyvcd."""
    import base64
    import shutil
    import subprocess
    import urllib.request

    from vcd.reader import TokenKind, tokenize

    by = open_page(browser, served)
    browser.find_element(by.ID, "scope-lanes").send_keys("MCP.plus.X1, DB31.DBX64.7, X1.position")
    seconds = browser.find_element(by.ID, "scope-seconds")
    seconds.clear()
    seconds.send_keys("3")
    browser.find_element(by.ID, "scope-apply").click()
    wait_until(lambda: "scope: 3 lanes" in messages(browser), "the lanes picked")
    from selenium.webdriver.support.ui import Select

    wait_until(lambda: len(Select(browser.find_element(by.ID, "scope-trigger")).options) == 3, "digital lanes")
    Select(browser.find_element(by.ID, "scope-trigger")).select_by_visible_text("MCP.plus.X1")
    status = browser.find_element(by.ID, "scope-status")
    assert status.text == "armed: waiting for MCP.plus.X1 rising"
    press(browser, "MCP.jog")
    wait_until(lambda: browser.find_element(by.ID, "mode").text == "mode JOG", "JOG mode")
    press(browser, "MCP.plus.X1", 0.5)
    wait_until(lambda: status.text.endswith("frozen") and status.text.startswith("triggered"), "triggered, frozen")
    shown = browser.execute_script("return scopeShown();")
    key = [value for _, value in shown["lanes"][0]["values"]]
    assert key[0] == 0 and 1 in key and key[-1] == 0, "the key goes 1 and back to 0 in the frozen window"
    first_one = key.index(1)
    assert shown["lanes"][0]["values"][first_one][0] == shown["triggeredAt"]
    assert 1 in [value for _, value in shown["lanes"][1]["values"]]  # the NC's traverse command followed
    assert shown["lanes"][2]["values"][-1][1] > 0  # X1 moved
    browser.execute_script("document.getElementById('scope').scrollIntoView();")
    shoot(browser, "scope")

    png = browser.find_element(by.ID, "scope-png")
    png.click()
    href = str(png.get_attribute("href"))
    assert href.startswith("data:image/png;base64,")
    image = base64.b64decode(href.split(",", 1)[1])
    assert image[:8] == b"\x89PNG\r\n\x1a\n"
    if os.environ.get("VC_UI_SCREENSHOTS"):
        (Path(os.environ["VC_UI_SCREENSHOTS"]) / "scope_saved.png").write_bytes(image)

    vcd = tmp_path / "scope.vcd"
    with urllib.request.urlopen(str(browser.find_element(by.ID, "scope-vcd").get_attribute("href")),
                                timeout=30) as response:
        vcd.write_bytes(response.read())
    with vcd.open("rb") as handle:
        tokens = list(tokenize(handle))
    names = {token.data.reference for token in tokens if token.kind is TokenKind.VAR}
    assert {"MCP.plus.X1", "basic.in.traversPlusCommandActive", "X1.position"} <= names, names
    vcd2fst = shutil.which("vcd2fst")
    if vcd2fst:
        fst = tmp_path / "scope.fst"
        converted = subprocess.run([vcd2fst, str(vcd), str(fst)], capture_output=True, text=True, timeout=60)
        assert converted.returncode == 0 and fst.stat().st_size > 0, converted.stderr
