"""``vc run --report DIR`` and ``vc run --plot``: an offline HTML page with the failing variants first, the
matrix of a campaign and a timing diagram per scenario, checked in headless Chromium; the diagrams' data."""

from __future__ import annotations

import io
import json
import os
import re
import shutil
import subprocess
import urllib.parse
from html.parser import HTMLParser
from pathlib import Path

import pytest
from rich.console import Console

from interfaces.links.inprocess import plc_programs
from vc.cli.main import main
from vc.harness.targets import simulation_for
from vc.scenario.command import EXIT_FAILED, EXIT_PASSED, run_command
from vc.scenario.language.loader import load_scenarios
from vc.scenario.outputs.timing import ANALOG, BUS, DIGITAL, timing_diagram
from vc.scenario.run.runner import run_one

ROOT = Path(__file__).resolve().parents[4]
FILES = Path(__file__).resolve().parents[1] / "campaign_files"
CAMPAIGN = str((FILES / "jog_campaign.yaml").relative_to(ROOT))  # 20 variants, 5 of them fail
PLAIN = "scenarios/foundation/jog_traverse.yaml"
CHROMIUM = shutil.which("chromium")
needs_chromium = pytest.mark.skipif(CHROMIUM is None and not os.environ.get("VC_REQUIRE_CHROMIUM"),
                                    reason="Debian's chromium is not installed (.ci/run installs it)")


@pytest.fixture(autouse=True)
def _in_repository(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


class _Page(HTMLParser):
    """The page's images, links, anchors and section headings."""

    def __init__(self) -> None:
        super().__init__()
        self.images: list[dict[str, str]] = []
        self.links: list[str] = []
        self.anchors: set[str] = set()
        self.headings: list[str] = []
        self._heading = False

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = {name: value or "" for name, value in attrs}
        if tag == "img":
            self.images.append(values)
        elif tag == "a" and "href" in values:
            self.links.append(values["href"])
        if "id" in values:
            self.anchors.add(values["id"])
        self._heading = tag == "h2"

    def handle_data(self, data: str) -> None:
        if self._heading:
            self.headings.append(data.strip())
            self._heading = False


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str, int]:
    directory = tmp_path_factory.mktemp("report")
    os.chdir(ROOT)
    output = io.StringIO()
    code = run_command([PLAIN, CAMPAIGN], simulation_for, plc_programs().keys(), jobs=2,
                       console=Console(file=output, width=300), trace_dir=directory / "traces",
                       report_dir=directory / "report")
    return directory / "report", output.getvalue(), code


def test_the_page_shows_the_failing_variants_first_then_the_matrix_and_the_diagrams(
        report: tuple[Path, str, int]) -> None:
    directory, output, code = report
    assert code == EXIT_FAILED
    assert f"report: {directory / 'index.html'}" in output
    text = (directory / "index.html").read_text(encoding="utf-8")
    page = _Page()
    page.feed(text)
    assert page.headings == ["Failing", "Matrices", "Timing diagrams", "All scenarios"]
    assert "<title>vc run: 5 of 21 failed</title>" in text
    failing = text.split("<h2>Failing</h2>", 1)[1].split("<h2>", 1)[0]
    assert failing.count('<tr class="fail">') == 5
    assert "X1.MD32020=40000,override=100,X1.sim.start_position=100" in failing
    assert "expected X1.velocity = 40000 ± 0.01, found 0.0" in failing
    matrix = text.split("<h2>Matrices</h2>", 1)[1].split("<h2>", 1)[0]
    assert "JOG velocities, overrides and start positions: JOG of X1 at its JOG velocity times the override" in matrix
    assert "<th>X1.MD32020</th><th>override</th><th>X1.sim.start_position</th><th>dwell</th>" in matrix
    assert matrix.count('<td class="num">') >= 20
    # the values of MD32020 with their passes and failures: 40000 fails at either override, 12000 at the limit
    assert '<td>40000</td><td class="num">0</td><td class="num"><span class="fail">4</span></td>' in matrix
    # 21 diagrams: the campaign's first variant, its 5 failures and the plain scenario
    assert len(page.images) == 7
    for image in page.images:
        assert (directory / urllib.parse.unquote(image["src"])).stat().st_size > 5000
        assert int(image["width"]) == 1200 and int(image["height"]) > 300
    for link in page.links:
        if link.startswith("#"):
            assert link[1:] in page.anchors
        else:
            assert (directory / urllib.parse.unquote(link)).exists(), link
    diagrams = text.split("<h2>Timing diagrams</h2>", 1)[1]
    assert diagrams.index('<span class="fail">FAIL</span>') < diagrams.index('<span class="pass">PASS</span>')
    assert "jog_traverse.gtkw" in diagrams


@needs_chromium
def test_the_page_loads_in_headless_chromium_with_every_image(report: tuple[Path, str, int],
                                                             tmp_path: Path) -> None:
    """A copy of the page with a script that lists every image's natural size once the page has loaded;
    Chromium prints the DOM after the load event."""
    assert CHROMIUM is not None, "chromium is required here (VC_REQUIRE_CHROMIUM is set)"
    directory = report[0]
    script = ('<script>window.addEventListener("load",function(){var r=[];for(const i of document.images)'
              '{r.push([i.getAttribute("src"),i.complete,i.naturalWidth,i.naturalHeight]);}'
              'var p=document.createElement("pre");p.id="image-check";p.textContent=JSON.stringify(r);'
              "document.body.appendChild(p);});</script>")
    check = directory / "image-check.html"
    check.write_text((directory / "index.html").read_text(encoding="utf-8").replace("</body>", script + "</body>"),
                     encoding="utf-8")
    try:
        dom = _dom_in_chromium(check, tmp_path)
    finally:
        check.unlink()
    found = re.search(r'<pre id="image-check">(.*?)</pre>', dom)
    assert found is not None, dom[-2000:]
    images = json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    assert len(images) == 7
    for source, complete, width, height in images:
        assert complete and width == 1200 and height > 300, source


def _dom_in_chromium(page: Path, tmp_path: Path) -> str:
    """The page's DOM after Debian's headless Chromium loaded it (and its scripts ran)."""
    assert CHROMIUM is not None, "chromium is required here (VC_REQUIRE_CHROMIUM is set)"
    done = subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                           "--disable-background-networking", "--disable-component-update", "--disable-sync",
                           "--no-first-run", f"--user-data-dir={tmp_path / 'profile'}",
                           "--virtual-time-budget=10000", "--dump-dom", page.as_uri()],
                          capture_output=True, text=True, timeout=180, check=False)
    assert done.returncode == 0 and "</html>" in done.stdout, done.stdout[-2000:] + done.stderr[-2000:]
    return done.stdout


@needs_chromium
def test_a_name_with_control_characters_shows_them_as_escapes_in_chromium(tmp_path: Path) -> None:
    """The page's title and headings show the name's escape sequence as text: nothing of it reaches the DOM."""
    output = io.StringIO()
    name = "a\\e[2K\\e[1GPASS\\u202e <b>bold</b>"  # YAML escapes: ESC, a right-to-left override, markup
    code = run_command([_short_failing(tmp_path, name)], simulation_for, plc_programs().keys(),
                       console=Console(file=output, width=300), report_dir=tmp_path / "report")
    assert code == EXIT_FAILED
    dom = _dom_in_chromium(tmp_path / "report" / "index.html", tmp_path)
    assert "a\\x1b[2K\\x1b[1GPASS\\u202e &lt;b&gt;bold&lt;/b&gt;" in dom
    assert not re.search("[\x00-\x08\x0b-\x1f\x7f-\x9f\u202a-\u202e]", dom)
    assert "<b>bold</b>" not in dom


def test_a_timing_diagram_has_lanes_steps_the_failure_and_the_expected_window() -> None:
    scenarios = load_scenarios([CAMPAIGN], plc_programs().keys())
    passed = timing_diagram(run_one(scenarios[0], simulation_for))
    assert passed is not None and passed.status == "PASS" and passed.failure_s is None
    kinds = {lane.name: lane.kind for lane in passed.lanes}
    assert kinds["MCP.plus.X1"] == DIGITAL and kinds["X1.basic.in.traversPlusCommandActive"] == DIGITAL
    assert kinds["MCP.feedOverride"] == BUS and kinds["X1.velocity"] == ANALOG and kinds["X1.position"] == ANALOG
    assert list(kinds)[:2] == ["MCP.feedOverride", "MCP.jog"]  # in the order the scenario names them
    assert [step.index for step in passed.steps] == list(range(1, 12))
    window = next(window for window in passed.windows if window.strong)
    assert window.lane == "X1.basic.in.traversPlusCommandActive" and window.label == "step 9: <= 0.03 s"
    plus = next(lane for lane in passed.lanes if lane.name == "MCP.plus.X1")
    assert window.start_s == plus.times[1] and abs(window.end_s - window.start_s - 0.03) < 1e-9
    velocity = next(lane for lane in passed.lanes if lane.name == "X1.velocity")
    assert max(velocity.values) == pytest.approx(500.0)  # 1000 mm/min at 50 %

    failed = timing_diagram(run_one(scenarios[19], simulation_for))
    assert failed is not None and failed.status == "FAIL"
    assert failed.failure.startswith("step 6 (expect) at ") and "expected X1.velocity = 40000" in failed.failure
    assert [step.index for step in failed.steps if step.failed] == [6]
    assert failed.failure_s == pytest.approx(failed.end_s)


def test_vc_run_plot_writes_one_variants_diagram(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    variant = f"{ROOT / CAMPAIGN}[X1.MD32020=40000,override=100,X1.sim.start_position=100,dwell=0.2s]"
    assert main(["run", "--plot", variant, "--plot-to", str(tmp_path / "one.svg")]) == EXIT_FAILED
    assert (tmp_path / "one.svg").read_text().lstrip().startswith("<?xml")
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.chdir(tmp_path)
    assert main(["run", "--plot", str(ROOT / PLAIN)]) == EXIT_PASSED  # no display: written here
    assert (tmp_path / "jog_traverse.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["run", "--plot", f"{ROOT / CAMPAIGN}[X1.MD32020=7]"]) == 2


def _short_failing(tmp_path: Path, name: str) -> str:
    path = tmp_path / "named.yaml"
    path.write_text(f'name: "{name}"\nmachine: turn_mill\nplc: basic_machine\nsteps:\n  - wait: 20ms\n'
                    "  - expect: {X1.position: 5}\n")
    return str(path)


def test_a_name_that_looks_like_mathtext_is_drawn_as_written(tmp_path: Path) -> None:
    """matplotlib's mathtext parser raised on ``$x^{$`` after the run, and no page was written."""
    output = io.StringIO()
    code = run_command([_short_failing(tmp_path, "$x^{$ and $\\\\alpha$")], simulation_for, plc_programs().keys(),
                       console=Console(file=output, width=300), report_dir=tmp_path / "report")
    assert code == EXIT_FAILED, output.getvalue()
    text = (tmp_path / "report" / "index.html").read_text(encoding="utf-8")
    page = _Page()
    page.feed(text)
    assert len(page.images) == 1 and "could not be drawn" not in text
    assert "$x^{$ and $\\alpha$" in text


def test_a_diagram_that_cannot_be_drawn_leaves_the_page(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from vc.scenario.outputs import diagram

    def broken(*arguments: object) -> tuple[int, int]:
        raise ValueError("no room for the lanes")

    monkeypatch.setattr(diagram, "save", broken)
    output = io.StringIO()
    code = run_command([_short_failing(tmp_path, "plain")], simulation_for, plc_programs().keys(),
                       console=Console(file=output, width=300), report_dir=tmp_path / "report")
    assert code == EXIT_FAILED
    text = (tmp_path / "report" / "index.html").read_text(encoding="utf-8")
    assert "the timing diagram could not be drawn: ValueError: no room for the lanes" in text
