"""spcotmhp.collector: the garbage collector paused while a planner starts (blocks nest and overlap across
threads; start-up ends with a freeze), and the command line's start-up."""

import gc
import json
import os
import subprocess
import sys
import threading
from pathlib import Path

from spcotmhp.collector import paused
from spcotmhp.persistence.io import load_model
from tests.helpers.server import INSTRUCTION, supervised_model_dir

ROOT = Path(__file__).resolve().parent.parent


def test_paused_blocks_nest_and_restore_the_state_they_found():
    assert gc.isenabled()
    with paused():
        assert not gc.isenabled()
        with paused():
            assert not gc.isenabled()
        assert not gc.isenabled()  # the inner block did not turn it on while the outer one runs
    assert gc.isenabled()
    gc.disable()
    try:
        with paused():
            assert not gc.isenabled()
        assert not gc.isenabled()  # off before: stays off
    finally:
        gc.enable()


def test_paused_blocks_overlapping_in_threads_resume_after_the_last():
    first_in, second_in, first_out = threading.Event(), threading.Event(), threading.Event()
    seen: dict[str, bool] = {}

    def first() -> None:
        with paused():
            first_in.set()
            second_in.wait(5)
        first_out.set()

    def second() -> None:
        first_in.wait(5)
        with paused():
            second_in.set()
            first_out.wait(5)
            seen["after the first ended"] = gc.isenabled()

    threads = [threading.Thread(target=first), threading.Thread(target=second)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(10)
    assert seen == {"after the first ended": False}
    assert gc.isenabled()


def test_paused_block_resumes_after_an_exception():
    try:
        with paused():
            raise ValueError("boom")
    except ValueError:
        pass
    assert gc.isenabled()


def run_child(code: str, *args: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


STARTUP = """
import gc, json
from spcotmhp.collector import end_startup, pause_for_startup
gc.disable() if {off} else None
pause_for_startup()
paused = not gc.isenabled()
end_startup()
first = (gc.isenabled(), gc.get_freeze_count() > 0)
end_startup()
print(json.dumps({{"paused": paused, "after": first, "again": gc.isenabled()}}))
"""


def test_startup_pause_ends_with_a_freeze_and_leaves_an_off_collector_off():
    assert run_child(STARTUP.format(off=False)) == {"paused": True, "after": [True, True], "again": True}
    # a process that turned collection off itself keeps it off (end_startup only undoes its own pause)
    assert run_child(STARTUP.format(off=True)) == {"paused": True, "after": [False, False], "again": False}


COMMAND = """
import gc, json, sys
from spcotmhp.collector import pause_for_startup
pause_for_startup()
from spcotmhp.cli import app
during = []
if sys.argv[1] == "plan":
    import spcotmhp.planning.planner as planner_module
    original = planner_module.HierarchicalPlanner.plan
    def spy(self, *a, **k):
        during.append(gc.isenabled())
        return original(self, *a, **k)
    planner_module.HierarchicalPlanner.plan = spy
app(sys.argv[1:], standalone_mode=False)
print(json.dumps({"during": during, "after": gc.isenabled(), "frozen": gc.get_freeze_count() > 0}))
"""


def test_plan_command_plans_with_the_collector_paused_then_resumes_it(tmp_path: Path):
    folder = supervised_model_dir("3LDK_06", tmp_path / "model")
    x, y = load_model(folder).mu[0]
    seen = run_child(COMMAND, "plan", str(folder), INSTRUCTION, "--start", f"{x:.3f}", f"{y:.3f}")
    # the text output plans twice (the first plan of the process, then the same plan warm: issue 25), both paused
    assert seen == {"during": [False, False], "after": True, "frozen": True}
    seen = run_child(COMMAND, "plan", str(folder), INSTRUCTION, "--start", f"{x:.3f}", f"{y:.3f}", "--json")
    assert seen == {"during": [False], "after": True, "frozen": True}


def test_other_commands_resume_the_collector_before_they_run():
    seen = run_child(COMMAND, "datasets")
    assert seen["after"] and seen["frozen"]


def test_the_command_line_entry_imports_no_dataset_or_server_module():
    code = (
        "import json, sys; from spcotmhp.collector import pause_for_startup; pause_for_startup(); "
        "import spcotmhp.cli; print(json.dumps(sorted(sys.modules)))"
    )
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    modules = json.loads(out.stdout.strip().splitlines()[-1])
    assert [m for m in modules if m.startswith(("spcotmhp.datasets", "spcotmhp.server", "asyncio"))] == []
