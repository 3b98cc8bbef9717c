"""Where numba's compiled kernels are kept (spcotmhp/numba_cache.py)."""

from __future__ import annotations

import os

from spcotmhp import numba_cache


def test_cache_dir_falls_back_to_user_cache(monkeypatch, tmp_path):
    # cache_dir_default sets os.environ itself: setenv first, so that monkeypatch restores the variable even when
    # it was unset (delenv of an unset variable records nothing, and the folder set below outlived this test:
    # every `spcotmhp serve` the later tests started compiled its kernels into an empty cache)
    monkeypatch.setenv("NUMBA_CACHE_DIR", "")
    monkeypatch.delenv("NUMBA_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(os, "access", lambda *a, **k: False)
    assert numba_cache.cache_dir_default() == str(tmp_path / "spcotmhp" / "numba")
    assert (tmp_path / "spcotmhp" / "numba").is_dir()
    monkeypatch.setenv("NUMBA_CACHE_DIR", "/somewhere")
    assert numba_cache.cache_dir_default() == "/somewhere"
