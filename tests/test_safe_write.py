"""Writing files and folders (spcotmhp/safe_write.py): modes follow the umask (issue 26: folders were 0700
whatever the umask, so a robot node running as another user could not read a model), and the staging folders a
killed save leaves are removed by the next save once they are older than the running process."""

from __future__ import annotations

import os
import stat
import time
from pathlib import Path

import pytest

from spcotmhp import safe_write
from spcotmhp.safe_write import atomic_write_text, build_folder, remove_stale


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077, 0o002])
def test_files_and_folders_follow_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        folder = build_folder(tmp_path / "out", lambda new: (new / "a.txt").write_text("a"))
        atomic_write_text(tmp_path / "b.txt", "b")
    finally:
        os.umask(old)
    assert _mode(folder) == 0o777 & ~umask
    assert _mode(folder / "a.txt") == 0o666 & ~umask
    assert _mode(tmp_path / "b.txt") == 0o666 & ~umask


def test_a_model_folder_follows_the_umask(tmp_path):
    from spcotmhp.persistence.io import save_model
    from tests.helpers.planning import home_model

    old = os.umask(0o022)
    try:
        folder = save_model(home_model(), tmp_path / "m")
    finally:
        os.umask(old)
    assert _mode(folder) == 0o755
    assert {_mode(p) for p in folder.iterdir()} == {0o644}


def test_only_stale_staging_folders_of_the_target_are_removed(tmp_path):
    before = safe_write.PROCESS_START - 100
    made = {}
    for name in (".m.new-abcd1234", ".m.old-x_y_z_01", ".m.check-0000aaaa", ".m.new-fresh123", ".m.new-short",
                 ".mm.new-abcd1234", ".m.backup", "m.new-abcd1234"):  # fmt: skip
        made[name] = tmp_path / name
        made[name].mkdir()
        (made[name] / "arrays.npz").write_bytes(b"x")
        if name != ".m.new-fresh123":
            for path in (made[name] / "arrays.npz", made[name]):
                os.utime(path, (before, before))
    touched = tmp_path / ".m.new-touched1"  # an old folder with a file written since this process started
    touched.mkdir()
    (touched / "arrays.npz").write_bytes(b"x")
    os.utime(touched, (before, before))
    removed = remove_stale(tmp_path / "m")
    assert sorted(p.name for p in removed) == [".m.check-0000aaaa", ".m.new-abcd1234", ".m.old-x_y_z_01"]
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == [".m.backup", ".m.new-fresh123", ".m.new-short", ".m.new-touched1", ".mm.new-abcd1234",
                    "m.new-abcd1234"]  # fmt: skip


def test_the_process_start_is_before_now_and_after_boot():
    assert time.time() - 3600 * 24 * 365 < safe_write.PROCESS_START <= time.time()


def test_the_process_start_is_precise_to_the_tick():
    """A staging folder left by a save killed just before a supervisor restarted the process is older than the
    new process: the start must not be rounded to whole seconds (the boot time of /proc/stat was)."""
    import subprocess
    import sys

    code = "from spcotmhp import safe_write; print(repr(safe_write.PROCESS_START))"
    before = time.time()
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    after = time.time()
    assert before - 0.05 <= float(out) <= after
