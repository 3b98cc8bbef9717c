"""The web page end to end in headless Chromium (Debian `chromium` driven by Playwright): click a start on the
map, submit "go to the bedroom via the corridor", see the path and the explanation.

Skips only when Playwright or the chromium executable is missing (`make system-deps` installs chromium)."""

from __future__ import annotations

import shutil
import subprocess
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from spcotmhp.persistence.io import load_model
from tests.helpers.server import INSTRUCTION, ServerProcess, start_near, supervised_model_dir, wall_point

sync_api = pytest.importorskip("playwright.sync_api", reason="the browser test needs playwright (extra 'dev')")
CHROMIUM = next(
    (
        p
        for p in (shutil.which("chromium"), shutil.which("chromium-browser"), "/usr/bin/chromium")
        if p and Path(p).is_file()
    ),
    None,
)
if CHROMIUM is None:
    pytest.skip(
        "chromium is not installed (apt-get install chromium; `make system-deps` does it)",
        allow_module_level=True,
    )
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]

WAIT_MS = 120_000


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    model_dir = supervised_model_dir("3LDK_06", tmp_path_factory.mktemp("web") / "3LDK_06")
    with ServerProcess([f"home={model_dir}"]) as srv:
        srv.model = load_model(model_dir)
        yield srv


@pytest.fixture()
def page(tmp_path):
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch_persistent_context(
            str(tmp_path / "profile"),
            executable_path=CHROMIUM,
            headless=True,
            args=ARGS,
            viewport={"width": 1280, "height": 1000},
        )
        try:
            pg = browser.new_page()
            # waits are for readiness, not speed (benchmarks/ measures speed): a loaded 2-core machine can take
            # more than Playwright's default 30 s to start the page's first plan; a hang still fails
            pg.set_default_timeout(WAIT_MS)
            errors: list[str] = []
            pg.on("pageerror", lambda exc: errors.append(str(exc)))
            pg.errors = errors
            log: list[str] = []  # for failure messages (diagnosis)
            pg.on("console", lambda msg: log.append(f"console {msg.type}: {msg.text}"))
            pg.on("requestfailed", lambda req: log.append(f"request failed: {req.method} {req.url}: {req.failure}"))
            pg.on("response", lambda r: r.status >= 400 and log.append(f"HTTP {r.status}: {r.request.method} {r.url}"))
            pg.log = log
            yield pg
        finally:
            browser.close()


def diagnosis(page, server) -> str:
    """What a failure message needs: the page's messages, its console and failed requests, the server's output."""
    shown = {}
    for selector in ("#error", "#start", "#explanation", "#words"):
        try:
            shown[selector] = page.text_content(selector, timeout=2_000)
        except sync_api.Error as exc:
            shown[selector] = f"(unreadable: {exc.message.splitlines()[0]})"
    lines = [f"page {page.url}: " + "; ".join(f"{k} = {v!r}" for k, v in shown.items())]
    lines += page.log[-30:] + [f"page error: {e}" for e in page.errors]
    lines += ["server output (tail):", server.output_tail()]
    return "\n".join(lines)


@contextmanager
def diagnosed(page, server) -> Iterator[None]:
    """A failed check or wait in the block fails with :func:`diagnosis` in its message."""
    try:
        yield
    except (AssertionError, sync_api.Error) as exc:
        raise AssertionError(f"{exc}\n--- diagnosis ---\n{diagnosis(page, server)}") from exc


def open_page(page, server) -> None:
    """Load the web page and wait until it takes clicks."""
    page.goto(server.url + "/")
    page.wait_for_selector("#overlay[data-ready='1']")


def ask(page, instruction: str) -> None:
    """Type ``instruction`` and press Plan."""
    page.fill("#instruction", instruction)
    page.click("#plan-button")


class HeldBack:
    """The page's requests to URLs that ``matches`` accepts are held back (Playwright's route API) until
    :meth:`release`; later ones pass."""

    def __init__(self, page, matches) -> None:
        self.page, self.held, self.released = page, [], False
        page.route(matches, self._route)

    def _route(self, route) -> None:
        route.continue_() if self.released else self.held.append(route)

    def wait(self) -> None:
        """Until a request is held back (route handlers run while Playwright waits)."""
        deadline = time.monotonic() + WAIT_MS / 1000
        while not self.held and time.monotonic() < deadline:
            self.page.wait_for_timeout(50)
        assert self.held, "the page sent no request to hold back"

    def release(self) -> None:
        self.released = True
        for route in self.held:
            route.continue_()


def click_world(page, xy):
    """Click the map at map-frame point ``xy`` (the page's own georeferencing: GET /map.json)."""
    info = page.evaluate("fetch('/map.json').then(r => r.json())")
    x0, x1, y0, y1 = info["extent"]
    box = page.locator("#overlay").bounding_box()
    page.mouse.click(
        box["x"] + (xy[0] - x0) / (x1 - x0) * box["width"],
        box["y"] + (y1 - xy[1]) / (y1 - y0) * box["height"],
    )


def test_click_start_plan_and_see_the_path(server, page):
    with diagnosed(page, server):
        open_page(page, server)  # the map is shown: test_the_page_is_ready_only_once_the_map_is_shown
        assert "corridor" in page.text_content("#words")
        start = start_near(server.model)
        click_world(page, start)
        assert _close(page.text_content("#start"), start), (page.text_content("#start"), start)
        ask(page, INSTRUCTION)
        page.wait_for_selector("#path")
        points = page.get_attribute("#path", "points").split()
        assert len(points) > 2
        explanation = page.text_content("#explanation")
        assert "corridor (waypoint)" in explanation and "bedroom" in explanation
        assert page.locator("circle.mark.goal").count() == 1 and page.locator("circle.mark.waypoint").count() == 1
        assert page.text_content("#error") == ""
        assert page.errors == []
        # not even the browser's own /favicon.ico request fails (a 404 in the console: second audit)
        assert [line for line in page.log if line.startswith(("HTTP", "console error"))] == []


def test_the_page_is_ready_only_once_the_map_is_shown(server, page):
    """The overlay that takes the clicks has the map image's size, so until the image has loaded it is an empty
    box no click reaches. The page used to say it was ready (data-ready) as soon as the map's georeferencing and
    place words had arrived: with the image held back here, a ready page whose click set no start."""
    image = HeldBack(page, lambda url: "/map.png" in url)
    with diagnosed(page, server):
        with page.expect_response(lambda r: "/places" in r.url):
            page.goto(server.url + "/")
        image.wait()
        page.wait_for_timeout(500)  # time for the page to act on the answers it has
        assert page.get_attribute("#overlay", "data-ready") != "1"
        image.release()
        page.wait_for_selector("#overlay[data-ready='1']")
        start = start_near(server.model)
        click_world(page, start)
        assert _close(page.text_content("#start"), start), (page.text_content("#start"), start)


def test_unknown_word_shows_the_message(server, page):
    with diagnosed(page, server):
        open_page(page, server)
        page.click("#plan-button")
        assert page.text_content("#error") == "Click on the map to set the start first."
        click_world(page, start_near(server.model))
        ask(page, "go to the garage")
        page.wait_for_function("document.getElementById('error').textContent.length > 0")
        assert page.text_content("#error").startswith("no known place word in 'go to the garage'")
        assert page.locator("#path").count() == 0


def test_a_failed_plan_clears_the_previous_one(server, page):
    """A plan, then an instruction that fails: the old path and explanation go, only the error stays (it used to
    look as if "go to the garage" had planned the bedroom path)."""
    with diagnosed(page, server):
        open_page(page, server)
        click_world(page, start_near(server.model))
        ask(page, INSTRUCTION)
        page.wait_for_selector("#path")
        assert "bedroom" in page.text_content("#explanation")
        ask(page, "go to the garage")
        page.wait_for_function("document.getElementById('error').textContent.length > 0")
        assert page.locator("#path").count() == 0 and page.locator("circle.mark").count() == 0
        assert page.text_content("#explanation") == "" and page.text_content("#hypotheses") == ""
        ask(page, INSTRUCTION)  # planning again works, and the error goes
        page.wait_for_selector("#path")
        assert page.text_content("#error") == ""
        click_world(page, start_near(server.model, "kitchen"))  # a new start: the plan from the old one goes
        assert page.locator("#path").count() == 0 and page.text_content("#explanation") == ""
        assert page.errors == []


def test_a_plan_answered_after_the_start_moved_is_not_drawn(server, page):
    """A plan is asked for, and the start is moved before its answer arrives (held back here): the late answer
    belongs to the old start, so the page drops it (it used to draw a path from a start no longer shown)."""
    answer = HeldBack(page, lambda url: url.endswith("/plan"))
    with diagnosed(page, server):
        open_page(page, server)
        click_world(page, start_near(server.model))
        ask(page, INSTRUCTION)
        answer.wait()
        click_world(page, start_near(server.model, "kitchen"))
        with page.expect_response(lambda r: r.url.endswith("/plan")) as late:
            answer.release()
        assert late.value.status == 200
        page.wait_for_timeout(500)  # time for the page to act on the answer
        assert page.locator("#path").count() == 0 and page.text_content("#explanation") == ""
        page.click("#plan-button")  # the plan from the start shown is drawn
        page.wait_for_selector("#path")
        assert "bedroom" in page.text_content("#explanation") and page.errors == []


def test_the_start_mark_leaves_the_label_under_it_readable(server, page):
    """The start is often set on a place's label (the demo starts at the entrance): the mark is a hollow ring
    with a dot of at most 2 px, drawn above the plan, and it takes no clicks."""
    with diagnosed(page, server):
        open_page(page, server)
        click_world(page, start_near(server.model))
        marks = page.eval_on_selector_all(
            "#start-mark circle",
            "cs => cs.map(c => [c.getAttribute('class'), c.getAttribute('fill'), parseFloat(c.getAttribute('r'))])",
        )
        assert marks and all(fill == "none" for kind, fill, _ in marks if kind == "ring")
        assert all(r <= 2 for kind, _, r in marks if kind == "dot")
        assert page.get_attribute("#start-mark", "pointer-events") == "none"
        ask(page, INSTRUCTION)
        page.wait_for_selector("#path")
        last = page.evaluate("document.getElementById('overlay').lastElementChild.id")
        assert last == "start-mark"
        goal = page.locator("circle.mark.goal")
        assert float(goal.get_attribute("fill-opacity")) <= 0.3  # the goal's label shows through its mark


def test_upload_a_wav_and_see_the_path(server, page, tmp_path):
    with diagnosed(page, server):
        pytest.importorskip("pocketsphinx", reason="speech needs pocketsphinx (extra 'speech')")
        espeak = shutil.which("espeak-ng")
        if espeak is None:
            pytest.skip("espeak-ng is not installed (apt-get install espeak-ng; `make system-deps` does it)")
        wav = tmp_path / "say.wav"
        wav.write_bytes(
            subprocess.run([espeak, "-v", "en-us", "--stdout", INSTRUCTION], capture_output=True, check=True).stdout
        )
        open_page(page, server)
        click_world(page, start_near(server.model))
        page.set_input_files("#wav", str(wav))
        page.click("#audio-button")
        page.wait_for_selector("#path")
        assert len(page.get_attribute("#path", "points").split()) > 2
        assert page.text_content("#hypotheses").startswith(f'Heard: "{INSTRUCTION}"')
        assert "corridor (waypoint)" in page.text_content("#explanation")
        assert page.errors == []
        click_world(page, wall_point(server.model))  # the plan fails: what was heard is still shown (second audit)
        page.click("#audio-button")
        page.wait_for_function("document.getElementById('error').textContent !== ''")
        assert page.text_content("#hypotheses").startswith(f'Heard: "{INSTRUCTION}"')
        assert page.locator("#path").count() == 0 and page.text_content("#explanation") == ""


def _close(shown: str, start: list[float]) -> bool:
    """The click lands on a pixel: the shown start is within a pixel (< 0.05 m at 60 px/m) of the target."""
    x, y = (float(v) for v in shown.removeprefix("Start: (").removesuffix(") m").split(", "))
    return abs(x - start[0]) < 0.05 and abs(y - start[1]) < 0.05


def test_click_a_spot_and_teach_its_name(server, page):
    """Last in this file: it changes the served model (a new place "alice's room")."""
    with diagnosed(page, server):
        import numpy as np

        from spcotmhp.metric.costmap import inflate

        model = server.model
        xy = model.map.cell_centres()[inflate(model.map, **model.costmap).free]
        spot = xy[int(np.argmax(np.sqrt(((xy[:, None] - model.mu[model.active_places][None]) ** 2).sum(-1)).min(1)))]
        open_page(page, server)
        click_world(page, spot)
        page.fill("#utterance", "this is alice's room")
        for n in range(3):
            page.click("#teach-button")
            page.wait_for_function(f"document.getElementById('taught').dataset.count === '{n + 1}'")
        assert "alice's room" in page.text_content("#taught"), page.text_content("#taught")
        assert "alice's" in page.text_content("#words")
        click_world(page, start_near(model))
        ask(page, "go to alice's room")
        page.wait_for_selector("#path")
        assert page.text_content("#explanation").find("alice's room") >= 0
        assert page.text_content("#error") == "" and page.errors == []
        # a failed teach leaves no "Learned: ..." line from the one before beside its error (second audit)
        page.fill("#utterance", "")
        page.click("#teach-button")
        page.wait_for_function("document.getElementById('error').textContent !== ''")
        assert page.text_content("#taught") == "", page.text_content("#taught")
        # a reload shows the taught map, not a cached picture from before the teach (second audit)
        page.reload()
        page.wait_for_selector("#overlay[data-ready='1']")
        shown = page.evaluate(PIXELS)
        page.evaluate(
            "async () => { const m = $('map'); m.src = `${state.info.image}&fresh=${Date.now()}`; await m.decode(); }"
        )
        assert page.evaluate(PIXELS) == shown


PIXELS = """() => {
  const img = document.getElementById('map'), canvas = document.createElement('canvas');
  [canvas.width, canvas.height] = [img.naturalWidth, img.naturalHeight];
  canvas.getContext('2d').drawImage(img, 0, 0);
  return canvas.toDataURL();
}"""  # the map image's pixels as the page shows them
