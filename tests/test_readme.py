"""The README runs as typed (issue 25): every shell and Python block, in order, in one clean temporary folder, as
a user who followed it from the top would; each ``text`` block after a runnable block lists lines its output must
hold ("..." stands for what varies: times, paths). A block is left out only where an HTML comment before it says
why: ``<!-- readme-test: skip (reason) -->`` (install steps, long runs), ``needs EXTRA`` (skipped only when that
extra is not installed), ``port`` (the block's port 8000 becomes a free port: no test binds a fixed port),
``file NAME`` (the block is saved as NAME for a later block), ``output of: COMMAND`` (the ``text`` block is the
output of COMMAND). Also: the README stays a user guide (at most 400 lines, its sections), its links resolve, and
its quick start is what CI runs."""

from __future__ import annotations

import contextlib
import importlib.util
import os
import re
import signal
import socket
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
SECTIONS = [
    "Quick start",
    "Tour",
    "Your own robot",
    "Reference: HTTP and ROS 2",
    "How to read a plan",
    "How instructions are understood",
    "Limits",
    "Results in short",
]
EXTRAS = {  # extra -> the modules it installs that the README's blocks use
    "server": ("fastapi", "uvicorn"),
    "speech": ("pocketsphinx",),
    "ros": ("rosbags",),
    "ros2": ("rclpy", "nav_msgs"),
}
DIRECTIVE = re.compile(r"<!--\s*readme-test:\s*(.*?)\s*-->")
FENCE = re.compile(r"^```(\w*)\s*$")
BLOCK_TIMEOUT = 300


@dataclass
class Block:
    """One fenced block of the README: its language, text, first line, section and directives."""

    lang: str
    text: str
    line: int
    section: str
    directives: list[str] = field(default_factory=list)

    @property
    def name(self) -> str:
        return f"{self.section.lower().replace(' ', '-').replace(':', '')}-L{self.line}"

    def directive(self, key: str) -> str | None:
        for d in self.directives:
            if d == key or d.startswith(key + " ") or d.startswith(key + ":"):
                return d[len(key) :].lstrip(" :")
        return None

    @property
    def runnable(self) -> bool:
        return self.lang in ("bash", "python") and self.directive("file") is None


def parse(text: str) -> list[Block]:
    """The fenced blocks in order, each with the directives of the comment lines just before it."""
    blocks: list[Block] = []
    section, pending, lines = "", [], text.splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("#") and not blocks or line.startswith(("## ", "### ")):
            section = line.lstrip("#").strip()
        if m := DIRECTIVE.search(line):
            pending += [d.strip() for d in re.split(r",(?![^()]*\))", m.group(1))]  # a reason may hold commas
        elif m := FENCE.match(line):
            start = i
            body = []
            i += 1
            while not lines[i].startswith("```"):
                body.append(lines[i])
                i += 1
            blocks.append(Block(m.group(1), "\n".join(body) + "\n", start + 1, section, pending))
            pending = []
        elif line.strip():
            pending = [] if not line.startswith("<!--") else pending
        i += 1
    return blocks


BLOCKS = parse(README.read_text(encoding="utf-8"))


def missing_extra(block: Block) -> str | None:
    extra = block.directive("needs")
    if extra is None:
        return None
    absent = [m for m in EXTRAS[extra] if importlib.util.find_spec(m) is None]
    return f"needs the extra '{extra}' ({', '.join(absent)} not installed)" if absent else None


def expected_lines(block: Block) -> list[str]:
    return [line for line in block.text.splitlines() if line.strip()]


def matches(pattern_line: str, output: str, any_port: bool = False) -> bool:
    """A text-block line against the output: "..." matches anything within one line; with ``any_port`` (the
    block's command ran where port 8000 may be taken) 8000 matches any port number."""
    pattern = "[^\n]*?".join(re.escape(part) for part in pattern_line.split("..."))
    if any_port:
        pattern = pattern.replace("8000", "[0-9]+")
    return re.search(pattern, output) is not None


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Workspace:
    """One clean folder where the blocks run in document order; a block first runs the blocks before it. The
    README's blocks by default; another document's (docs/ros2.md's, tests/ros/test_ros2_doc.py) with ``blocks``."""

    def __init__(self, folder: Path, blocks: list[Block] | None = None) -> None:
        self.folder = folder
        self.blocks = BLOCKS if blocks is None else blocks
        self.done: dict[int, str] = {}  # block index -> its output
        self.failed: dict[int, str] = {}
        bin_dir = str(Path(sys.executable).parent)
        self.env = {
            **os.environ,
            "PATH": bin_dir + os.pathsep + os.environ.get("PATH", ""),
            "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
            "ROS_LOG_DIR": str(folder / ".ros-log"),
            "NO_COLOR": "1",
        }

    def run_through(self, index: int) -> str:
        for k in range(index + 1):
            if k in self.failed:
                raise AssertionError(f"block {self.blocks[k].name} failed earlier:\n{self.failed[k]}")
            if k not in self.done:
                self.run(k)
        return self.done.get(index, "")

    def run(self, k: int) -> None:
        block = self.blocks[k]
        if (name := block.directive("file")) is not None:
            (self.folder / name).write_text(block.text, encoding="utf-8")
            self.done[k] = ""
            return
        if (command := block.directive("output of")) is not None:
            self.done[k] = self.execute(command, "bash", k)
            self.check(block, self.done[k])
            return
        if block.lang == "text":
            previous = next((j for j in range(k - 1, -1, -1) if self.blocks[j].runnable), None)
            if previous is not None and previous in self.done and not self.skip_reason(self.blocks[previous]):
                self.check(block, self.done[previous])
            self.done[k] = ""
            return
        if not block.runnable or self.skip_reason(block):
            self.done[k] = ""
            return
        self.done[k] = self.execute(block.text, block.lang, k)

    @staticmethod
    def skip_reason(block: Block) -> str | None:
        if (reason := block.directive("skip")) is not None:
            return reason
        return missing_extra(block)

    def execute(self, text: str, lang: str, k: int) -> str:
        if "port" in self.blocks[k].directives:
            text = text.replace("8000", str(free_port()))
        text = re.sub(r"ROS_DOMAIN_ID=\d+", f"ROS_DOMAIN_ID={90 + os.getpid() % 11}", text)
        if lang == "python":
            script = self.folder / f".readme_block_{k}.py"
            script.write_text(text, encoding="utf-8")
            argv = [sys.executable, str(script)]
        else:
            argv = ["bash", "-e", "-o", "pipefail", "-c", text]
        proc = subprocess.Popen(
            argv,
            cwd=self.folder,
            env=self.env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        try:
            out, _ = proc.communicate(timeout=BLOCK_TIMEOUT)
        except subprocess.TimeoutExpired:
            # SIGINT first, as Ctrl+C: Python flushes what it buffered and prints where it waited (the report says
            # what hung); SIGKILL only what does not stop within 10 s
            os.killpg(proc.pid, signal.SIGINT)
            try:
                out, _ = proc.communicate(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                out, _ = proc.communicate()
            self.failed[k] = f"timed out after {BLOCK_TIMEOUT} s:\n{out[-6000:]}"
            raise AssertionError(self.failed[k]) from None
        finally:
            with contextlib.suppress(ProcessLookupError):  # a server or node the block started and did not stop
                os.killpg(proc.pid, signal.SIGKILL)
        if proc.returncode != 0:
            self.failed[k] = f"exit status {proc.returncode}:\n{out[-3000:]}"
            raise AssertionError(f"block {self.blocks[k].name} failed with " + self.failed[k])
        return out

    def check(self, block: Block, output: str) -> None:
        any_port = "port" in block.directives
        missing = [line for line in expected_lines(block) if not matches(line, output, any_port)]
        assert not missing, f"{block.name}: the output lacks {missing}\n--- output ---\n{output[-3000:]}"


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Workspace:
    return Workspace(tmp_path_factory.mktemp("readme"))


CHECKED = [k for k, b in enumerate(BLOCKS) if b.runnable or b.lang == "text" or b.directive("file") is not None]


@pytest.mark.parametrize("k", CHECKED, ids=[BLOCKS[k].name for k in CHECKED])
def test_block_runs_as_typed(k: int, workspace: Workspace):
    run_block(workspace, k)


def run_block(workspace: Workspace, k: int) -> None:
    """Run block ``k`` of the workspace's document (and those before it); a text block checks its block's output.
    Skips (pytest) a block left out, or needing an extra that is not installed."""
    blocks = workspace.blocks
    block = blocks[k]
    if block.lang == "text" and block.directive("output of") is None:
        source = next((j for j in range(k - 1, -1, -1) if blocks[j].runnable), None)
        assert source is not None, f"{block.name}: an output with no block before it"
        block = blocks[source]
    if block.runnable and (reason := Workspace.skip_reason(block)):
        pytest.skip(reason)
    workspace.run_through(k)


def test_every_left_out_block_says_why():
    for block in BLOCKS:
        if block.directive("skip") is not None:
            assert re.fullmatch(r"\(.{10,}\)", block.directive("skip") or ""), f"{block.name}: skip without a reason"
        if (extra := block.directive("needs")) is not None:
            assert extra in EXTRAS, f"{block.name}: unknown extra {extra!r}"
    langs = {b.lang for b in BLOCKS}
    assert langs <= {"bash", "python", "text"}, f"blocks of no known kind: {langs}"


def test_the_readme_is_a_user_guide():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 400
    headings = [line[3:] for line in text.splitlines() if line.startswith("## ")]
    assert [h for h in SECTIONS if h not in headings] == []


def test_links_resolve():
    text = README.read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#]+?)(?:#[^)]*)?\)", text)
    local = [t for t in targets if "://" not in t]
    assert local and [t for t in local if not (ROOT / t).exists()] == []
    for doc in sorted((ROOT / "docs").glob("*.md")):
        for target in re.findall(r"\]\(([^)#]+?)(?:#[^)]*)?\)", doc.read_text(encoding="utf-8")):
            assert "://" in target or (doc.parent / target).exists(), f"{doc.name} links to missing {target}"


def test_the_quick_start_is_two_commands_and_ci_runs_the_second():
    quick = next(b for b in BLOCKS if b.section == "Quick start" and b.lang == "bash")
    commands = [line.split("#")[0].strip() for line in quick.text.splitlines() if line.split("#")[0].strip()]
    assert commands == ["make demo", "make test"]
    ci = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines() if not line.startswith("#")]
    assert "make test" in ci
    makefile = (ROOT / "Makefile").read_text()
    assert re.search(r"^demo:", makefile, re.M) and re.search(r"^test:", makefile, re.M)


def test_the_parser_reads_directives_and_text_blocks():
    text = (
        "## A\n\n<!-- readme-test: skip (an install step) -->\n```bash\nmake\n```\n\nprose\n\n"
        "<!-- readme-test: needs ros2, port -->\n```bash\nspcotmhp ros2 m\n```\n\n```text\nout ... put\n```\n"
    )
    a, b, c = parse(text)
    assert a.directive("skip") == "(an install step)" and a.section == "A" and a.line == 4
    assert b.directive("needs") == "ros2" and "port" in b.directives and b.runnable
    assert c.lang == "text" and not c.runnable and c.directives == []
    assert matches("out ... put", "out and put") and not matches("out ... put", "put out")
    assert not matches("out ... put", "out\nput") and matches("at 8000/", "at 8123/", any_port=True)
    d = parse("<!-- readme-test: skip (long, slow runs), port -->\n```bash\nx\n```\n")[0]
    assert d.directive("skip") == "(long, slow runs)" and "port" in d.directives
