"""One home for writing files and folders safely: refuse to clobber, write atomically, swap folders atomically.

* ``check_output(path, overwrite, inputs)``: a command's output file may replace an existing file only with
  ``--overwrite``, and never one of the command's own inputs (compared as the same file on disk, so
  ``costmap map.yaml --out ./map.yaml`` and a hard link count too), nor a folder.
* ``atomic_write(path, write)``: ``write(tmp)`` fills a temporary file beside ``path`` which is then renamed
  over it (``os.replace``): readers see the old file or the new one, never half of one; a failure (an
  exception, a full disk) leaves the old file untouched and no temporary behind.
* ``swap_folder(new, target)``: put the finished folder ``new`` at ``target``. When ``target`` exists the two
  are exchanged in one ``renameat2(RENAME_EXCHANGE)`` on Linux, so ``target`` names the old folder or the new
  one at every instant; elsewhere (or on file systems without it) two renames leave a moment without it.
  The old folder is removed afterwards.

Files and folders are created with the modes the process's umask gives (0o666 / 0o777 masked, as ``open`` and
``mkdir`` do), never a fixed 0o700 or 0o644, so a model folder saved under umask 022 is readable by a robot node
running as another user, and one saved under 077 by its owner only. A save killed mid-way (SIGKILL, power loss)
leaves its hidden staging folder ``.NAME.new-XXXXXXXX`` (or ``.NAME.old-XXXXXXXX``) beside ``NAME``; the next
save of ``NAME`` removes those whose newest entry is older than the running process (``PROCESS_START``): no
process alive since then can still be writing them.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
import re
import secrets
import shutil
import tempfile
import time
from collections.abc import Callable, Iterable
from pathlib import Path

from spcotmhp.errors import SpcotmhpError

ErrorType = type[SpcotmhpError]


def same_file(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name the same existing file or folder (symlinks, ``..`` and hard links seen
    through), or the same path when one does not exist yet."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return Path(os.path.abspath(a)) == Path(os.path.abspath(b))


def check_output(
    path: Path,
    overwrite: bool,
    inputs: Iterable[Path] = (),
    error: ErrorType = SpcotmhpError,
    option: str = "--out",
    suffix: str | None = None,
) -> Path:
    """Refuse an output file that is one of ``inputs``, a folder, or (without ``overwrite``) an existing file,
    or whose name does not end in ``suffix`` (what will be written: a CSV in "cm.png" misleads every viewer);
    the message names the option, the file and the way out."""
    path = Path(path)
    for given in inputs:
        if given is not None and Path(given).exists() and same_file(path, Path(given)):
            raise error(f"{option} {path} is one of this command's inputs ({given}); write elsewhere")
    if path.is_dir():
        raise error(f"{option} {path} is a folder; give a file name")
    if suffix is not None and path.suffix.lower() != suffix:
        raise error(f"{option} {path}: this writes a {suffix[1:].upper()} file; give a name ending in {suffix}")
    if (path.exists() or path.is_symlink()) and not overwrite:
        raise error(f"{option} {path} exists; give --overwrite to replace it, or choose another name")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise error(f"{option} {path}: the folder {folder} does not exist")
    return path


def outside_model(path: Path, model_dir: Path, option: str) -> None:
    """Refuse an output inside the model folder ``model_dir``: the folder holds only the model, and ``teach``
    (which replaces it whole) refuses one with other files in it."""
    if Path(model_dir).is_dir() and Path(path).resolve().is_relative_to(Path(model_dir).resolve()):
        raise SpcotmhpError(
            f"{option} {path} is inside the model folder {model_dir}, which must hold only the model "
            "(teach refuses a folder with other files); write elsewhere"
        )


def atomic_write(path: Path, write: Callable[[Path], object], error: ErrorType = SpcotmhpError) -> Path:
    """Call ``write(tmp)`` on a fresh empty temporary file beside ``path`` (its mode from the umask), flush it to
    disk and rename it to ``path``; the temporary is removed on any failure, which propagates (an ``OSError``
    becomes ``error``)."""
    path = Path(path)
    try:
        tmp = _fresh(path.parent, f".{path.name[:80]}.", ".tmp", _new_file)
    except OSError as exc:
        raise error(f"cannot write {path}: {exc.strerror or exc}") from None
    try:
        write(tmp)
        with open(tmp, "rb+") as handle:
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        tmp.unlink(missing_ok=True)
        raise error(f"cannot write {path}: {exc.strerror or exc}") from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def atomic_write_text(path: Path, text: str, error: ErrorType = SpcotmhpError) -> Path:
    """``atomic_write`` of UTF-8 text."""
    return atomic_write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"), error)


def fresh_sibling(target: Path, tag: str) -> Path:
    """A new empty folder beside ``target`` (hidden: ``.NAME.TAG-XXXXXXXX``) to build a replacement in, with
    the mode the umask gives; stale staging folders of ``target`` are removed first (:func:`remove_stale`)."""
    target.parent.mkdir(parents=True, exist_ok=True)
    remove_stale(target)
    return _fresh(target.parent, f".{target.name[:80]}.{tag}-", "", os.mkdir)


def _fresh(folder: Path, prefix: str, suffix: str, make: Callable[[Path], object]) -> Path:
    """``make(path)`` on a new random name ``prefix + 8 hex digits + suffix`` in ``folder`` (FileExistsError
    retried with another name)."""
    for _ in range(100):
        path = folder / f"{prefix}{secrets.token_hex(4)}{suffix}"
        try:
            make(path)
        except FileExistsError:
            continue
        return path
    raise FileExistsError(f"no free name {prefix}*{suffix} in {folder}")


def _new_file(path: Path) -> None:
    os.close(os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))  # the umask applies, as for open()


def _process_start() -> float:
    """The wall-clock time this process started: on Linux the time since boot now (CLOCK_BOOTTIME, which
    /proc/self/stat's start time counts in) less the process's start after boot (clock ticks, 10 ms: at most that
    early, on the safe side), subtracted from the time now; elsewhere the time this module was imported. (The
    boot time of /proc/stat is rounded to whole seconds: a save killed less than a second before a supervisor
    restarted the process looked newer than it, and its staging folder was never removed.)"""
    try:
        ticks = int(Path("/proc/self/stat").read_text().rsplit(")", 1)[1].split()[19])
        since = time.clock_gettime(time.CLOCK_BOOTTIME) - ticks / os.sysconf("SC_CLK_TCK")
        return time.time() - since - 0.01
    except (OSError, ValueError, IndexError, AttributeError):
        return time.time()


PROCESS_START = _process_start()
STAGING_TAGS = ("new", "old", "check")


def remove_stale(target: Path) -> list[Path]:
    """Remove the staging folders ``.NAME.{new,old,check}-XXXXXXXX`` of ``target`` (left by a killed save) whose
    folder and entries were all last changed before this process started; returns them. A folder that cannot
    be removed is left (the save goes on)."""
    pattern = re.compile(rf"\.{re.escape(target.name[:80])}\.({'|'.join(STAGING_TAGS)})-[A-Za-z0-9_]{{8}}")
    removed: list[Path] = []
    try:
        siblings = [p for p in target.parent.iterdir() if pattern.fullmatch(p.name)]
    except OSError:
        return removed
    for folder in siblings:
        try:
            if folder.is_symlink() or not folder.is_dir():
                continue
            newest = max([folder.lstat().st_mtime] + [e.lstat().st_mtime for e in folder.iterdir()])
        except OSError:
            continue
        if newest < PROCESS_START:
            shutil.rmtree(folder, ignore_errors=True)
            removed.append(folder)
    return removed


def swap_folder(new: Path, target: Path) -> None:
    """Move the finished folder ``new`` to ``target``, replacing a folder there (module docstring)."""
    if not target.exists() and not target.is_symlink():
        os.rename(new, target)
        _fsync_dir(target.parent)
        return
    if _exchange(new, target):  # target is now the new folder, ``new`` the old one
        _fsync_dir(target.parent)
        shutil.rmtree(new, ignore_errors=True)
        return
    old = Path(tempfile.mkdtemp(prefix=f".{target.name[:80]}.old-", dir=target.parent))
    os.rmdir(old)
    os.rename(target, old)
    try:
        os.rename(new, target)
    except BaseException:
        os.rename(old, target)
        raise
    _fsync_dir(target.parent)
    shutil.rmtree(old, ignore_errors=True)


def _exchange(a: Path, b: Path) -> bool:
    """``renameat2(a, b, RENAME_EXCHANGE)``; False when the platform or file system lacks it."""
    libc_name = ctypes.util.find_library("c")
    if libc_name is None or not hasattr(os, "fsencode"):
        return False
    try:
        libc = ctypes.CDLL(libc_name, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    result = renameat2(at_fdcwd, os.fsencode(str(a)), at_fdcwd, os.fsencode(str(b)), rename_exchange)
    return result == 0


def _fsync_dir(folder: Path) -> None:
    with contextlib.suppress(OSError):
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def build_folder(
    target: Path, fill: Callable[[Path], object], error: ErrorType = SpcotmhpError, action: str | None = None
) -> Path:
    """Build the folder ``target`` whole or not at all: ``fill(staging)`` writes into a fresh sibling, which
    then replaces ``target`` (:func:`swap_folder`); on any failure the sibling is removed and ``target`` is
    left as it was (an ``OSError`` becomes ``error``: "cannot <action>: <reason>", action "write <target>")."""
    target = Path(target)
    action = action or f"write {target}"
    try:
        staging = fresh_sibling(target, "new")
    except OSError as exc:
        raise error(f"cannot {action}: {exc.strerror or exc}") from None
    try:
        fill(staging)
        swap_folder(staging, target)
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        raise error(f"cannot {action}: {exc.strerror or exc}") from None
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return target
