"""The experiment runner, the evaluate/reproduce commands and the tables, on a bundled SIGVerse home."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from spcotmhp.cli import app
from spcotmhp.datasets import load_bundled
from spcotmhp.errors import SpcotmhpError
from spcotmhp.evaluation.context import build_context
from spcotmhp.evaluation.methods import METHODS, MOVE_MODELS
from spcotmhp.evaluation.runner import check_methods, evaluate, evaluate_chunk, run_local
from spcotmhp.evaluation.tables import PAPER, markdown_table
from spcotmhp.evaluation.tasks import make_tasks, subset
from spcotmhp.evaluation.work import run_method
from spcotmhp.planning.protocol import Planner

EXE = Path(sys.executable).with_name("spcotmhp")
ALL = list(METHODS)
GRID = [m for m in ALL if not m.endswith("-ma")]  # the moving average leaves the grid (and may cut a wall)


@pytest.fixture(scope="module")
def ctx():
    return build_context(load_bundled("3LDK_01"), "supervised", seed=0)


@pytest.fixture(scope="module")
def advanced(ctx):
    return subset(make_tasks(ctx.dataset, "advanced", ctx.adjacency, places=ctx.places).tasks, 6, seed=1)


def outcomes(records):
    return {
        (r.task_index, r.method): (
            r.outcome.success,
            r.outcome.n_success,
            r.outcome.w_success,
            round(r.outcome.p, 9),
            r.outcome.ratio,
        )
        for r in records
    }


def test_context_reuses_one_planning_graph(ctx):
    assert ctx.planners["hpp1"].hpp.graph is ctx.planner.graph is ctx.planners["hpp2-smoothed"].hpp.graph
    assert ctx.planners["spcotmhp"] is ctx.planner
    assert ctx.adjacency_source == "adjacency.csv"
    assert ctx.notes()["places"][7:10] == ["bedroom"] * 3


def test_every_method_plans_from_the_start(ctx, advanced):
    for task in advanced:
        for name in ALL:
            path = run_method(name, ctx, task, np.random.default_rng(0))
            assert path is not None and len(path) >= 1, name
            np.testing.assert_allclose(path[0], task.start_xy, atol=1e-9, err_msg=name)
            cells = ctx.dataset.map.world_to_cell(path)
            assert name not in GRID or ctx.dataset.map.free[cells[:, 0], cells[:, 1]].all(), name


def test_every_method_is_a_planner_looked_up_by_name(ctx, advanced):
    """Each method is a Planner: a sentence and a start pose give a Plan whose path starts there, whose cells are
    the path's cells and whose explanation names the start and goal places; the same rng gives the same plan."""
    start = advanced[0].start_xy
    for name in ALL:
        planner = ctx.planners[name]
        assert isinstance(planner, Planner), name
        plan = planner.plan("go to the bedroom via the kitchen", start, rng=np.random.default_rng(3))
        again = planner.plan("go to the bedroom via the kitchen", start, rng=np.random.default_rng(3))
        np.testing.assert_array_equal(plan.path, again.path, err_msg=name)
        np.testing.assert_allclose(plan.path[0], start, atol=1e-9, err_msg=name)
        if name in GRID:  # the moving average leaves the grid
            np.testing.assert_allclose(ctx.dataset.map.cell_to_world(plan.cells), plan.path, err_msg=name)
        assert plan.explanation.endswith(" m") or "; " in plan.explanation, name
        assert plan.places[-1].role == "goal" and plan.length_m >= 0, name


def test_move_models(ctx, advanced):
    # A* moves like SpCoTMHP (8-connected, as the reference length l); SpCoNavi keeps the paper's action set
    # {stay, up, down, left, right}
    steps = {name: set() for name in GRID}
    for task in advanced:
        for name in GRID:
            cells = ctx.dataset.map.world_to_cell(run_method(name, ctx, task, np.random.default_rng(0)))
            steps[name] |= set(np.abs(np.diff(cells, axis=0)).sum(axis=1).tolist())
    for name in ("spcotmhp", "astar", "hpp1", "hpp2", "hpp1-smoothed", "spcotmhp-unsmoothed"):
        assert steps[name] == {1, 2}, name
    for name in ("spconavi-viterbi", "spconavi-astar"):
        assert steps[name] == {1}, name
    assert MOVE_MODELS["astar"] == "8-connected" and MOVE_MODELS["spconavi-viterbi"].startswith("4-connected")


def test_results_do_not_depend_on_order_or_chunking(ctx, advanced):
    a = evaluate_chunk(ctx, advanced, ["astar", "hpp1", "spconavi-astar"], seed=3)
    b = evaluate_chunk(ctx, advanced[::-1], ["spconavi-astar", "hpp1", "astar"], seed=3)
    assert outcomes(a) == outcomes(b)
    c = evaluate_chunk(ctx, advanced, ["astar", "hpp1", "spconavi-astar"], seed=4)
    assert outcomes(a) != outcomes(c)  # the seed matters for the sampling baselines


def test_process_pool_matches_in_process(ctx, advanced):
    methods = ["spcotmhp", "astar", "hpp2"]
    one = run_local(ctx, advanced, methods, 0, workers=1, advance=lambda n: None)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr("spcotmhp.evaluation.work.CHUNK", 2)  # three chunks on two processes
        two = run_local(ctx, advanced, methods, 0, workers=2, advance=lambda n: None)
    assert outcomes(one) == outcomes(two)


def test_evaluate_result_layout():
    ds = load_bundled("3LDK_01")
    res = evaluate([ds], "advanced", ALL, max_tasks=4, workers=1, quiet=True)
    assert set(res) >= {"homes", "mean", "notes", "task", "params"}
    keys = {"spl", "n_spl", "w_spl", "wn_spl", "success", "time_median_s", "time_p95_s", "n_tasks"}
    apart = res["notes"]["3LDK_01"]["start_in_waypoint"]
    for metrics in (res["homes"]["3LDK_01"], res["mean"]):
        assert list(metrics) == ALL
        for m in metrics.values():
            assert keys <= set(m) and m["n_tasks"] == 4 - apart and m["seeds"] == 1
            assert all(0.0 <= m[k] <= 1.0 for k in ("spl", "n_spl", "w_spl", "wn_spl", "success"))
            assert m["wn_spl"] <= min(m["w_spl"], m["n_spl"]) + 1e-12 and m["n_spl"] <= m["spl"] + 1e-12
    assert res["notes"]["3LDK_01"]["adjacency"] == "adjacency.csv"
    assert res["notes"]["3LDK_01"]["n_tasks_all"] == 648
    assert res["moves"] == {m: MOVE_MODELS[m] for m in ALL}
    basic = evaluate([ds], "basic", ["spcotmhp"], max_tasks=3, workers=1, quiet=True)
    assert "w_spl" not in basic["mean"]["spcotmhp"] and "wn_spl" not in basic["mean"]["spcotmhp"]


def test_check_methods():
    assert check_methods(["hpp1", " astar", "hpp1"]) == ["hpp1", "astar"]
    with pytest.raises(SpcotmhpError, match="unknown method\\(s\\) dijkstra; accepted: spcotmhp, astar"):
        check_methods(["dijkstra"])
    with pytest.raises(SpcotmhpError, match="\\(none given\\)"):
        check_methods([""])


def test_cli_evaluate_json():
    out = CliRunner().invoke(
        app,
        [
            "evaluate",
            "3LDK_05",
            "--task",
            "basic",
            "--method",
            "spcotmhp,hpp2",
            "--max-tasks",
            "5",
            "--workers",
            "1",
            "--seeds",
            "3",
            "--json",
        ],
    )
    assert out.exit_code == 0, out.output
    res = json.loads(out.stdout)
    assert list(res["homes"]) == ["3LDK_05"] and list(res["mean"]) == ["spcotmhp", "hpp2"]
    assert res["mean"]["spcotmhp"]["n_tasks"] == 5 and res["seeds"] == 3
    # supervised parameters: SpCoTMHP draws nothing (one run counts for every seed), HPP draws its targets
    assert res["mean"]["spcotmhp"]["spl_sd"] == 0.0 and res["mean"]["hpp2"]["seeds"] == 3
    assert {"spl", "spl_sd", "n_spl", "n_spl_sd", "success_sd"} <= set(res["mean"]["hpp2"])
    # every metric has its bootstrap interval over tasks, which holds the mean; the deterministic methods listed
    for m in res["mean"].values():
        assert {"spl_ci", "strict_spl_ci", "success_ci"} <= set(m)
        assert m["spl_ci"][0] - 1e-12 <= m["spl"] <= m["spl_ci"][1] + 1e-12
    assert res["deterministic"] == ["spcotmhp"] and "spl_ci" in res["homes"]["3LDK_05"]["hpp2"]


@pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
def test_deterministic_methods_alone_over_several_seeds():
    """Audit item 6: with supervised parameters and only methods that draw nothing, seeds after the first
    reuse the first seed's outcomes (they used to leave no method to run and fail with "unknown method(s)")."""
    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.evaluation.runner import evaluate

    res = evaluate([load_bundled("3LDK_05")], "basic", ["spcotmhp"], max_tasks=3, workers=1, seeds=2, quiet=True)
    assert res["seeds"] == 2 and list(res["mean"]) == ["spcotmhp"]
    assert res["mean"]["spcotmhp"]["n_tasks"] == 3 and res["mean"]["spcotmhp"]["spl_sd"] == 0.0


def test_seeds_are_bounded():
    from spcotmhp.evaluation.runner import evaluate
    from spcotmhp.limits import MAX_SEEDS

    with pytest.raises(ValueError, match=f"seeds must be an integer in \\[1, {MAX_SEEDS}\\], got {MAX_SEEDS + 1}"):
        evaluate([], "basic", ["spcotmhp"], seeds=MAX_SEEDS + 1, quiet=True)
    from spcotmhp.evaluation.runner import evaluate_home

    with pytest.raises(ValueError, match="workers must be an integer in \\[1, 256\\], got 1000000"):
        evaluate_home(None, [], ["spcotmhp"], workers=10**6)


@pytest.mark.parametrize(
    "args,message",
    [
        (
            ["evaluate", "3LDK_01", "--method", "spcotmhp,teleport"],
            "error: unknown method(s) teleport; accepted:",
        ),
        (
            ["evaluate", "3LDK_01", "--task", "expert"],
            "error: --task must be one of basic, advanced, got 'expert'",
        ),
        (
            ["evaluate", "no-such-home"],
            "error: no-such-home is neither a dataset folder nor a bundled dataset",
        ),
        (
            ["evaluate", "3LDK_01", "--params", "guessed"],
            "error: --params must be one of supervised, learned",
        ),
        (
            ["evaluate", "3LDK_01", "--connectivity", "magic"],
            "error: --connectivity must be one of auto, hmm, walk, map, got 'magic'",
        ),
        (["reproduce", "--seeds", "0"], "Invalid value for '--seeds'"),
    ],
)
def test_cli_errors(args, message):
    proc = subprocess.run([str(EXE), *args], capture_output=True, text=True, timeout=120, check=False)
    assert proc.returncode == 2
    assert message in proc.stderr
    assert "Traceback" not in proc.stderr


def test_reproduce_checks_its_output_path_before_running(tmp_path):
    for out, message in [
        (
            tmp_path / "missing" / "x.md",
            (f"error: --out {tmp_path / 'missing' / 'x.md'}: the folder {tmp_path / 'missing'} does not exist"),
        ),
        (tmp_path, f"error: --out {tmp_path} is a folder; give a file name such as"),
        (tmp_path / "mine.md", f"error: --out {tmp_path / 'mine.md'} exists; give --overwrite to replace it"),
    ]:
        if out.name == "mine.md":
            out.write_text("someone's notes")
        proc = subprocess.run(
            [str(EXE), "reproduce", "--out", str(out), "--max-tasks", "1"],
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        assert proc.returncode == 2 and message in proc.stderr and "Traceback" not in proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1  # refused before any home was loaded or planned
    assert (tmp_path / "mine.md").read_text() == "someone's notes"


@pytest.mark.parametrize(
    "args,backend,address",
    [
        (["--ray"], "ray", "local"),  # bare, last
        (["--ray", "--json"], "ray", "local"),  # bare, followed by an option
        (["--ray", "ray://head:10001"], "ray", "ray://head:10001"),
        (["--ray=auto"], "ray", "auto"),
        ([], "local", None),
    ],
)
def test_ray_option_takes_an_optional_address(monkeypatch, args, backend, address):
    seen = {}

    def fake(homes, kind, methods, params, seed, workers, max_tasks, backend, ray_address, **kw):
        seen.update(backend=backend, address=ray_address, homes=[h.name for h in homes])
        return {"task": kind, "params": params, "seed": seed, "homes": {}, "mean": {}, "notes": {}}

    monkeypatch.setattr("spcotmhp.evaluation.runner.evaluate", fake)
    out = CliRunner().invoke(app, ["evaluate", "3LDK_01", *args, "--json"])
    assert out.exit_code == 0, out.output
    assert seen == {"backend": backend, "address": address, "homes": ["3LDK_01"]}


def test_markdown_tables_put_paper_rows_beside_ours():
    ours = {
        "spcotmhp": {
            "spl": 0.9,
            "n_spl": 0.88,
            "w_spl": 0.9,
            "wn_spl": 0.87,
            "success": 1.0,
            "time_median_s": 0.0012,
            "time_p95_s": 0.004,
            "n_tasks": 10,
        },
        "spconavi-viterbi": {
            "spl": 0.4,
            "n_spl": 0.3,
            "w_spl": 0.6,
            "wn_spl": 0.01,
            "success": 0.4,
            "time_median_s": 0.08,
            "time_p95_s": 0.2,
            "n_tasks": 10,
        },
    }
    text = markdown_table("advanced", ours)
    lines = text.splitlines()
    assert lines[0] == "### Table 5: advanced task"
    i = lines.index("| SpCoTMHP | paper | 0.922 | 0.906 | 0.794 | 0.781 |  |  | 390 ms |  |")
    assert lines[i + 1] == (
        "| SpCoTMHP (ours: our smoothing) | ours | 0.900 | 0.900 | 0.880 | 0.870 | 1.000 | 0.000 | 1.2 ms / 4 ms | 10 |"
    )
    # the paper has no Viterbi row in Table 5: ours stands alone, labelled
    assert (
        "| SpCoNavi (Viterbi) | ours | 0.400 | 0.600 | 0.300 | 0.010 | 0.400 | 0.000 | 80 ms / 200 ms | 10 |" in lines
    )
    assert sum(" paper " in ln for ln in lines) == len(PAPER["advanced"])
    basic = markdown_table("basic", {})
    assert "| SpCoNavi (Viterbi) | paper | 0.976 | 0.965 |  |  | 2,680 s |  |" in basic
    # several seeds: mean ± sd; a smoothed HPP row shares HPP's paper row; our N (via) columns when present
    spread = {
        "hpp1": {**ours["spcotmhp"], "spl_sd": 0.01, "seeds": 3},
        "hpp1-smoothed": {**ours["spcotmhp"], "n_spl_via": 0.5, "wn_spl_via": 0.4, "seeds": 3},
    }
    lines = markdown_table("advanced", spread).splitlines()
    assert lines[2].startswith("Success: the path's last pose within the robot's inscribed radius (0.22 m)")
    assert "N-SPL (via)" in lines[4] and sum(ln.startswith("| HPP-I (path cost) | paper") for ln in lines) == 1
    assert lines[lines.index(next(ln for ln in lines if ln.startswith("| HPP-I (path cost) | ours"))) + 1].startswith(
        "| HPP-I + our smoothing | ours |"
    )
    assert "| HPP-I (path cost) | ours | 0.900 ± 0.010 | 0.900 |" in "\n".join(lines)


def test_markdown_tables_give_intervals_for_deterministic_rows_and_the_strict_rule_beside():
    row = {
        "spl": 0.9,
        "spl_ci": [0.85, 0.95],
        "spl_sd": 0.0,
        "n_spl": 0.8,
        "n_spl_ci": [0.7, 0.9],
        "success": 1.0,
        "success_ci": [1.0, 1.0],
        "strict_spl": 0.95,
        "strict_n_spl": 0.75,
        "strict_success": 0.9,
        "time_median_s": 0.001,
        "time_p95_s": 0.002,
        "n_tasks": 4,
        "seeds": 2,
    }
    drawn = {**row, "spl_sd": 0.05}
    lines = markdown_table("basic", {"spcotmhp": row, "hpp1": drawn}, deterministic=["spcotmhp"]).splitlines()
    assert "| Strict: SPL / N-SPL / Success |" in lines[4]
    assert (
        "| SpCoTMHP (ours: our smoothing) | ours | 0.900 [0.850, 0.950] | 0.800 [0.700, 0.900] | 1.000 [1.000, "
        "1.000] | 0.950 / 0.750 / 0.900 | 0.000 | 1 ms / 2 ms | 4 |"
    ) in lines
    assert "| HPP-I (path cost) | ours | 0.900 ± 0.050 | 0.800 | 1.000 | 0.950 / 0.750 / 0.900 |" in "\n".join(lines)
    # learned parameters that every seed learned alike: the sd is rounding of equal figures, the interval shows
    alike = {**row, "spl_sd": 1e-17, "n_spl_sd": 0.0}
    assert "| HPP-I (path cost) | ours | 0.900 [0.850, 0.950] |" in markdown_table("basic", {"hpp1": alike})


def test_reproduce_markdown_says_how_each_method_moves():
    from spcotmhp.evaluation.tables import experiment_markdown

    m = {
        "spl": 0.9,
        "n_spl": 0.8,
        "w_spl": 0.9,
        "wn_spl": 0.8,
        "success": 1.0,
        "time_median_s": 0.001,
        "time_p95_s": 0.002,
        "n_tasks": 1,
    }
    basic = {
        "homes": {"h": {"spconavi-astar": m}},
        "mean": {"spconavi-astar": m},
        "notes": {},
        "params": "supervised",
        "seed": 0,
        "moves": {"spconavi-astar": MOVE_MODELS["spconavi-astar"], "astar": "8-connected"},
    }
    text = experiment_markdown(basic, {**basic, "homes": {}}, "Tables", "About.")
    assert (
        "Moves: SpCoNavi (A* approximation) 4-connected + stay (the paper's SpCoNavi action set); A* 8-connected. "
        "SPL's reference length l is an 8-connected geodesic."
    ) in text


def test_home_without_adjacency_uses_the_map_connectivity_rule():
    from spcotmhp.datasets.synthetic import generate_environment
    from spcotmhp.learning.connectivity import map_adjacency
    from spcotmhp.learning.supervised import fit_supervised

    ds = generate_environment("house", seed=4)
    ds.adjacency = None
    ctx = build_context(ds, "supervised", seed=0)
    assert ctx.adjacency_source == "connectivity from the map (no adjacency.csv)"
    np.testing.assert_array_equal(ctx.adjacency, map_adjacency(fit_supervised(ds, adjacency="map"), ds.map))
    res = evaluate([ds], "basic", ["spcotmhp", "hpp2"], max_tasks=3, workers=1, quiet=True)
    assert res["notes"][ds.name]["adjacency"] == "connectivity from the map (no adjacency.csv)"
    assert res["mean"]["spcotmhp"]["n_tasks"] == 3


def test_scale_benchmark_runs_on_a_small_office(capsys):
    import importlib.util

    spec = importlib.util.spec_from_file_location("scale", Path(__file__).parents[2] / "benchmarks" / "scale.py")
    scale = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(scale)
    assert scale.main(["--rooms", "6", "--size", "200", "--queries", "4"]) == 0
    out = capsys.readouterr().out
    assert "| precompute (planning graph) |" in out and "| plan, median / p95 |" in out
    assert "| failed plans | 0 of 4 |" in out


@pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")
def test_evaluate_a_given_model_folder(tmp_path):
    """Issue 24 item 5: `evaluate DATASET --model MODEL_DIR` scores a model folder as it is: the supervised fit
    saved and evaluated gives the same figures as --params supervised; a model of another map is refused."""
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.persistence.io import save_model

    ds = load_bundled("3LDK_05")
    save_model(fit_supervised(ds), tmp_path / "m05")
    args = ["evaluate", "3LDK_05", "--method", "spcotmhp,spcotmhp-paper", "--max-tasks", "6", "--workers", "1"]
    given = CliRunner().invoke(app, [*args, "--model", str(tmp_path / "m05"), "--seeds", "1", "--json"])
    fitted = CliRunner().invoke(app, [*args, "--seeds", "1", "--json"])
    assert given.exit_code == 0 and fitted.exit_code == 0, given.output + fitted.output
    a, b = json.loads(given.stdout), json.loads(fitted.stdout)
    assert a["params"] == "model" and a["model"] == str(tmp_path / "m05")
    assert a["deterministic"] == ["spcotmhp", "spcotmhp-paper"]
    for method in ("spcotmhp", "spcotmhp-paper"):
        for key in ("spl", "n_spl", "success", "strict_spl", "spl_ci", "n_tasks"):
            assert a["mean"][method][key] == b["mean"][method][key], (method, key)
    two = CliRunner().invoke(app, ["evaluate", "3LDK_05", "3LDK_06", "--model", str(tmp_path / "m05")])
    assert isinstance(two.exception, SpcotmhpError)
    assert str(two.exception) == "--model evaluates one model on the one dataset it was made on; got 2 datasets"
    wrong = CliRunner().invoke(app, ["evaluate", "3LDK_06", "--model", str(tmp_path / "m05"), "--max-tasks", "1"])
    assert isinstance(wrong.exception, SpcotmhpError)
    assert str(wrong.exception).startswith("3LDK_06: the model's map is not the dataset's (cells that differ: ")
