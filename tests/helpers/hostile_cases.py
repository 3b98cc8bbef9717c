"""Issue 26 from the outside: every case of the issue, and hostile variants of them, run as a user runs them
(the ``spcotmhp`` command, or a short library script in a fresh interpreter) and judged by what the user sees.

Each case builds its inputs under a root folder (model folders whose values were changed behind a resealed
manifest, sparse files of gigabytes, PGM/PNG headers, a map split by a closed door, a busy port) and runs one
command. The outcome is judged by :func:`judge`: the exit status is the expected one (0, or 2 for a refusal),
a refusal prints exactly one ``error:`` line naming what the case expects and nothing else on stderr, and no
output holds a traceback. ``tests/test_hostile_cases.py`` runs them as tests;
``python -m tests.helpers.hostile_cases [ROOT] [NAME ...]`` prints a table with each case's exit status and
wall time (the acceptance of issue 26 asks for < 3 s each on a quiet machine).

A library case (``lib:NAME``) runs :func:`library_case` in a fresh interpreter: it prints ``ok: ...`` and exits
0, or, on a library error (:class:`~spcotmhp.errors.SpcotmhpError`), prints ``error: ...`` and exits 2, as the
command line does; anything else escapes as a traceback (exit 1).
"""

from __future__ import annotations

import re
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from tests.helpers.hostile_inputs import (
    _HELD,
    bmp_strip,
    busy_port_bad_model,
    busy_port_missing_model,
    costmap_of,
    dev_zero_image,
    fifo_image,
    lib,
    library_case,
    pgm_cap_square,
    pgm_comment_50mb,
    pgm_comments_many,
    pgm_huge_header_sparse,
    pgm_spaces_50mb,
    pgm_strip,
    pgm_strip_wide,
    pgm_zeros_50mb,
    plain_pgm_cap,
    plain_ppm,
    png_strip,
    png_text_50mb,
    png_ztxt_bomb,
    yaml_alias_bomb,
    yaml_tiny_resolution,
)
from tests.helpers.hostile_models import (
    SPARSE,
    _counts_zeroed,
    _deep_info,
    _empty_word,
    _events_far,
    _extra_member,
    _float16_mu,
    _huge_int_K,
    _image_fifo,
    _map_is,
    _map_origin,
    _map_resolution,
    _mu_far,
    _no_active_places,
    _phi_negative,
    _psi_identity,
    _scatter_huge,
    _scatter_negative,
    _sigma_not_pd,
    _space_word,
    _theta_without_D,
    _W_one_word,
    child_env,
    door_model,
    door_plan,
    edited,
    grown,
    learner_edited,
    learner_grown,
    rewritten,
    template_model,
    template_start,
)

__all__ = ["CASES", "Case", "Outcome", "judge", "run", "template_model", "door_model", "template_start"]
EXE = str(Path(sys.executable).with_name("spcotmhp"))


@dataclass
class Case:
    """One hostile input: ``build(root)`` writes it and returns the command (argv after ``spcotmhp``, or
    ``["lib:NAME", ...]``); the answer must exit with ``status`` and (a refusal) say ``expect`` (a regex)."""

    name: str
    item: str  # the item it belongs to, or "variant"
    build: Callable[[Path], list[str]]
    status: int = 2
    expect: str = ""
    slow: bool = False  # more than a few seconds to build or run: left out of the quick test run
    env: dict = field(default_factory=dict)


@dataclass
class Outcome:
    status: int
    seconds: float
    stdout: str
    stderr: str

    @property
    def error_lines(self) -> list[str]:
        return [line for line in self.stderr.splitlines() if line.strip()]


CASES: list[Case] = [
    # -- values a checksum cannot judge (issue item 1) --
    Case("place_size 1e308", "values", edited(("hyper", "place_size", 1e308)), expect="place_size"),
    Case("Sigma x 1e-300", "values", edited(("array", "Sigma", "scale", 1e-300)), expect="Sigma"),
    Case("Sigma x 1e150", "values", edited(("array", "Sigma", "scale", 1e150)), expect="Sigma"),
    Case("mu NaN", "values", edited(("array", "mu", "entry", float("nan"))), expect="mu"),
    Case("W +inf", "values", edited(("array", "W", "entry", float("inf"))), expect="W"),
    Case("Sigma not PD", "values", rewritten(_sigma_not_pd), expect="Sigma"),
    Case("pi x 2 (sums to 2)", "values", edited(("array", "pi", "scale", 2.0)), expect="pi"),
    Case("psi column zeroed", "values", edited(("array", "psi", "zero-column", 0.0)), expect="psi"),
    Case("phi negative, rows sum to 1", "values", rewritten(_phi_negative), expect="phi"),
    Case("alpha -1", "values", edited(("hyper", "alpha", -1.0)), expect="alpha"),
    Case("nu0 0.5", "values", edited(("hyper", "nu0", 0.5)), expect="nu0"),
    Case("kappa0 1e300", "values", edited(("hyper", "kappa0", 1e300)), expect="kappa0"),
    Case("hyper K 0", "values", edited(("hyper", "K", 0)), expect=r"\bK\b"),
    Case("V0 1e-300 I", "values", edited(("hyper", "V0", [[1e-300, 0.0], [0.0, 1e-300]])), expect="V0"),
    Case("off_name -1", "values", edited(("hyper", "off_name", -1.0)), expect="off_name"),
    Case("costmap inflation 1e308", "values", edited(("costmap", "inflation_radius", 1e308)), expect="inflation"),
    # -- variants: other keys, other arrays --
    Case("v: costmap inflation 1e4 m (in range)", "variant", edited(("costmap", "inflation_radius", 1e4)), 0),
    Case("v: costmap inscribed 1e4 m (in range)", "variant", edited(("costmap", "inscribed_radius", 1e4)), 2, ""),
    Case("v: place_size 1e5 (the bound)", "variant", edited(("hyper", "place_size", 1e5)), 0),
    Case("v: m0 strings", "variant", edited(("hyper", "m0", ["a", "b"])), expect="m0"),
    Case("v: hyper L 10**20", "variant", edited(("hyper", "L", 10**20)), expect=r"\bL\b"),
    Case("v: feature_weight NaN", "variant", edited(("info", "feature_weight", float("nan"))), expect="feature_weight"),
    Case("v: means 990 km away", "variant", rewritten(_mu_far), 2, ""),
    Case("v: no active place", "variant", rewritten(_no_active_places), 2, ""),
    Case("v: mu float16 overflow", "variant", rewritten(_float16_mu), expect="mu"),
    Case("v: npz member ../../evil", "variant", rewritten(_extra_member), expect="unknown member"),
    Case("v: theta without D", "variant", rewritten(_theta_without_D), expect="theta"),
    Case("v: empty vocabulary word", "variant", rewritten(_empty_word), expect="vocabulary"),
    Case("v: whitespace vocabulary word", "variant", rewritten(_space_word), expect="vocabulary"),
    Case("v: K of 5000 digits", "variant", rewritten(_huge_int_K), expect="model.json"),
    Case("v: info nested 100000 deep", "variant", rewritten(_deep_info), expect="model.json"),
    Case("v: map resolution 1e-300", "variant", rewritten(_map_resolution), expect="resolution"),
    Case("v: map origin 1e308", "variant", rewritten(_map_origin), expect="origin"),
    Case("v: psi the identity", "variant", rewritten(_psi_identity), 0),
    Case("v: W all mass on one word", "variant", rewritten(_W_one_word), expect="kitchen"),
    Case("v: model.json map -> arrays.npz", "variant", rewritten(_map_is("arrays.npz")), expect="map"),
    Case("v: model.json map -> .", "variant", rewritten(_map_is(".")), expect="map"),
    Case("v: model.json map -> /etc/passwd", "variant", rewritten(_map_is("/etc/passwd")), expect="map"),
    Case("v: map image a FIFO (unlisted)", "variant", rewritten(_image_fifo), expect="pipe.pgm"),
    Case("v: teach: learner counts zeroed", "variant", learner_edited(_counts_zeroed), expect="learner"),
    Case("v: teach: learner scatter -1e6", "variant", learner_edited(_scatter_negative), expect="learner"),
    Case("v: teach: learner scatter 1e300", "variant", learner_edited(_scatter_huge), expect="learner"),
    Case("v: teach: learner events at 1e300 m", "variant", learner_edited(_events_far), expect="learner"),
    # -- sizes (issue item 2) --
    Case("arrays.npz 8 GiB sparse", "sizes", grown("arrays.npz", SPARSE, False), expect="arrays.npz"),
    Case("v: arrays.npz 8 GiB, manifest lists it", "variant", grown("arrays.npz", SPARSE, True), expect="arrays.npz"),
    Case("v: map.pgm 8 GiB, manifest lists it", "variant", grown("map.pgm", SPARSE, True), expect="map.pgm"),
    Case("v: model.json 8 GiB, manifest lists it", "variant", grown("model.json", SPARSE, True), expect="model.json"),
    Case("v: manifest.json 8 GiB", "variant", grown("manifest.json", SPARSE, False), expect="manifest"),
    Case("v: learner.npz at learner.json's E, T caps", "variant", learner_grown, expect="learner"),
    Case("PGM 50 MB comment", "sizes", costmap_of("m.pgm", pgm_comment_50mb), expect="m.pgm"),
    Case("PGM 1 x 16,000,000", "sizes", costmap_of("m.pgm", pgm_strip), expect="m.pgm"),
    Case("v: PGM 16,000,000 x 1, one-line header", "variant", costmap_of("m.pgm", pgm_strip_wide), expect="m.pgm"),
    Case("v: PGM 50 MB of spaces", "variant", costmap_of("m.pgm", pgm_spaces_50mb), expect="m.pgm"),
    Case("v: PGM 50 MB of leading zeros", "variant", costmap_of("m.pgm", pgm_zeros_50mb), expect="m.pgm"),
    Case("v: PGM 5,000,000 empty comments", "variant", costmap_of("m.pgm", pgm_comments_many), expect="m.pgm"),
    Case("v: PGM 8 GiB comment (sparse)", "variant", costmap_of("m.pgm", pgm_huge_header_sparse), expect="m.pgm"),
    Case("v: plain PGM (P2) 4000 x 4000", "variant", costmap_of("m.pgm", plain_pgm_cap), expect="plain"),
    Case("v: plain PPM (P3) 1000 x 1000", "variant", costmap_of("m.ppm", plain_ppm), expect="plain"),
    Case("v: map image a FIFO", "variant", costmap_of("m.pgm", fifo_image), expect="not a regular file"),
    Case("v: map image -> /dev/zero", "variant", costmap_of("m.pgm", dev_zero_image), expect="not a regular file"),
    Case("v: PNG 16,000,000 x 1", "variant", costmap_of("m.png", png_strip), expect="m.png"),
    Case("v: PNG 50 MB tEXt", "variant", costmap_of("m.png", png_text_50mb), 0),
    Case("v: PNG zTXt of 500 MB", "variant", costmap_of("m.png", png_ztxt_bomb), expect="m.png"),
    Case("v: BMP 16,000,000 x 1", "variant", costmap_of("m.bmp", bmp_strip), expect="m.bmp"),
    Case("v: map YAML alias bomb", "variant", yaml_alias_bomb, expect="map.yaml"),
    Case("v: map resolution 1e-300", "variant", yaml_tiny_resolution, expect="resolution"),
    Case("v: PGM 4000 x 4000 (the pixel cap)", "variant", costmap_of("m.pgm", pgm_cap_square), 0, slow=True),
    # -- a map cut by a closed door (issue item 4) --
    Case("door: goal in the start's small region", "regions", door_plan("go to the bedroom", 6, 5), 0),
    Case(
        "door: goal only behind the door",
        "regions",
        door_plan("go to the kitchen", 6, 5),
        expect="the kitchen is not reachable from here.*the free space is cut",
    ),
    Case(
        "v: door: waypoint behind the door",
        "variant",
        door_plan("go to the bedroom via the corridor", 6, 5),
        expect="the corridor is not reachable",
    ),
    Case("v: door: start in the wall", "variant", door_plan("go to the bedroom", 5, 10), expect="start"),
    # -- small things (issue item 5) --
    Case("serve: busy port, missing model", "small", busy_port_missing_model, expect="no-such-model"),
    Case("v: serve: busy port, Sigma x 1e-300", "variant", busy_port_bad_model, expect="Sigma"),
    Case("umask 022", "small", lib("umask-022"), 0),
    Case("v: umask 077", "variant", lib("umask-077"), 0),
    Case("v: umask 002", "variant", lib("umask-002"), 0),
    Case("SIGKILLed save, next save cleans", "small", lib("staging-after-kill"), 0),
    Case("save_model overwrite=False", "small", lib("save-default-no-overwrite"), expect="already holds a model"),
    Case('start ["1", "2"]', "small", lib("start-strings"), expect="start"),
    Case('v: start np.array(["1", "2"])', "variant", lib("start-numpy-strings"), expect="start"),
    Case("v: start b'12'", "variant", lib("start-bytes"), expect="start"),
    Case('v: start "1 2"', "variant", lib("start-string"), expect="start"),
    Case("v: start (True, False)", "variant", lib("start-bools"), expect="start"),
    Case("v: start of 3 numbers", "variant", lib("start-three"), expect="start"),
    Case("v: start [[1, 2]]", "variant", lib("start-nested"), expect="start"),
    Case("v: start a dict", "variant", lib("start-dict"), expect="start"),
    Case("v: start complex", "variant", lib("start-complex"), expect="start"),
    Case("v: start NaN", "variant", lib("start-nan"), expect="start"),
    Case("v: start 1e308", "variant", lib("start-huge"), expect="start"),
    Case("v: start object array", "variant", lib("start-object-array"), expect="start"),
]


# ---- running and judging ------------------------------------------------------------------------------------
def run(case: Case, root: Path, timeout: float = 120.0) -> tuple[list[str], Outcome]:
    """Build ``case`` under ``root`` and run it in a fresh process; (command, outcome)."""
    args = case.build(root)
    if args[0].startswith("lib:"):
        argv = [sys.executable, "-m", "tests.helpers.hostile_cases", "--lib", args[0][4:], *args[1:]]
    else:
        argv = [EXE, *args]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            argv, capture_output=True, text=True, timeout=timeout, env={**child_env(), **case.env}, cwd=root
        )
        outcome = Outcome(proc.returncode, time.perf_counter() - t0, proc.stdout, proc.stderr)
    except subprocess.TimeoutExpired as exc:
        outcome = Outcome(-9, time.perf_counter() - t0, str(exc.stdout or ""), f"timed out after {timeout} s")
    finally:
        for sock in _HELD:
            sock.close()
        _HELD.clear()
    return args, outcome


def judge(case: Case, outcome: Outcome) -> str:
    """'' when ``outcome`` is what ``case`` asks (module docstring), else what is wrong."""
    text = outcome.stdout + outcome.stderr
    if "Traceback" in text:
        return "traceback: " + outcome.stderr.strip().splitlines()[-1][:200]
    if outcome.status != case.status:
        return f"exit {outcome.status}, expected {case.status}: {(outcome.stderr or outcome.stdout).strip()[-200:]}"
    if case.status == 2:
        lines = outcome.error_lines
        if len(lines) != 1 or not lines[0].startswith("error: "):
            return f"not one error: line on stderr: {lines[:3]}"
        if case.expect and not re.search(case.expect, lines[0]):
            return f"the error does not say {case.expect!r}: {lines[0][:200]}"
    return ""


def _shown(args: list[str], root: Path) -> str:
    return " ".join(a if len(a) < 60 else a[:57] + "..." for a in args).replace(str(root) + "/", "")


def main(argv: list[str]) -> int:
    import tempfile

    if argv[:1] == ["--lib"]:
        from spcotmhp.errors import SpcotmhpError

        try:
            print("ok: " + library_case(argv[1], Path(argv[2])))
        except SpcotmhpError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        return 0
    root = Path(argv[0]) if argv and not argv[0].startswith("-") else Path(tempfile.mkdtemp(prefix="hostile-"))
    names = argv[1:] if argv and not argv[0].startswith("-") else []
    root.mkdir(parents=True, exist_ok=True)
    template_model(root)
    door_model(root)
    print(f"{'case':44s} {'exit':>4s} {'wall s':>7s}  {'judged':8s} command / first line")
    bad = 0
    for case in CASES:
        if names and not any(n in case.name for n in names):
            continue
        args, outcome = run(case, root)
        verdict = judge(case, outcome)
        bad += bool(verdict)
        first = (outcome.error_lines or outcome.stdout.strip().splitlines() or [""])[0]
        print(
            f"{case.name[:44]:44s} {outcome.status:4d} {outcome.seconds:7.2f}  {'ok' if not verdict else 'FAIL':8s} "
            f"{_shown(args, root)}"
        )
        print(f"{'':44s} {'':4s} {'':7s}  {'':8s} -> {(verdict or first)[:160]}")
    print(f"{bad} case(s) failed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
