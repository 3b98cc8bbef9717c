"""Online learning (issue 15): the collapsed conditional, streaming real homes, teaching a learned model a new
name (library, CLI, HTTP), bad teaching, the learner state in model folders, truncation growth, timing."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from scipy.stats import multivariate_t

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.errors import TeachingError
from spcotmhp.evaluation.online_eval import dataset_events
from spcotmhp.evaluation.table6 import score_run
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.distributions import GaussianStats, NIWGaussians
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP, TeachingEvent
from spcotmhp.learning.posterior import TruncationWarning
from spcotmhp.metric.costmap import inflate
from spcotmhp.persistence.io import load_model, save_model
from spcotmhp.teaching.teach import planner_for, teach
from tests.helpers.server import start_near, supervised_model_dir, wall_point

ALICE = "this is alice's room"


def home(name: str):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_bundled(name, lang="en")


def new_spot(model) -> np.ndarray:
    """The robot cell farthest from every place mean: a spot of the home that no place covers."""
    robot = inflate(model.map, **model.costmap).free
    xy = model.map.cell_centres()[robot]
    d = np.sqrt(((xy[:, None, :] - model.mu[model.active_places][None]) ** 2).sum(-1)).min(axis=1)
    return xy[int(np.argmax(d))]


@pytest.fixture(scope="module")
def batch_dir(tmp_path_factory):
    """A short batch fit of 3LDK_01 (its learner state included), saved."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)
        est = SpCoTMHP(iterations=30, seed=1).fit(home("3LDK_01"))
    return save_model(est.model_, tmp_path_factory.mktemp("online") / "m")


def test_predictive_is_the_student_t_of_the_niw_posterior():
    rng = np.random.default_rng(0)
    X = rng.normal([1.0, -2.0], [0.4, 0.7], size=(9, 2))
    hyper = Hyperparameters()
    st = CollapsedState(2, 1, 1, None, hyper)
    st.n_k[0], st.sx[0], st.sxx[0] = len(X), X.sum(axis=0), X.T @ X
    niw = NIWGaussians(2, np.asarray(hyper.m0), hyper.kappa0, np.asarray(hyper.V0), hyper.nu0)
    m, kappa, V, nu = niw.posterior(GaussianStats(st.n_k, st.sx, st.sxx))
    x = np.array([1.3, -1.1])
    for k in range(2):  # a place with data and an empty one (the prior predictive)
        dof = nu[k] - 1.0
        want = multivariate_t(m[k], V[k] * (kappa[k] + 1) / (kappa[k] * dof), df=dof).logpdf(x)
        assert st.log_predictive(x)[k] == pytest.approx(want, rel=1e-9)


def test_streaming_a_home_finds_its_places_and_concepts():
    data = home("3LDK_05")
    learner = OnlineSpCoTMHP(map=data.map, check_map=False, seed=0)
    for event in dataset_events(data):
        learner.partial_fit([event])
    scores = score_run(data, learner.places_, learner.concepts_)
    assert scores["nmi_i"] > 0.9 and scores["nmi_c"] > 0.9, scores
    # each update's time is recorded (its speed is measured by benchmarks/online_learning.py, not asserted here)
    assert len(learner.update_times_) == data.n_events and min(learner.update_times_) > 0.0


def test_updates_are_reproducible_however_they_are_split():
    events = dataset_events(home("3LDK_06"))[:40]
    one = OnlineSpCoTMHP(seed=3).partial_fit(events)
    two = OnlineSpCoTMHP(seed=3)
    for i in range(0, 40, 7):
        two.partial_fit(events[i : i + 7])
    assert np.array_equal(one.places_, two.places_) and np.array_equal(one.concepts_, two.concepts_)


def test_truncation_grows_then_warns_at_its_maximum():
    events = [TeachingEvent(10.0 * r, 0.0, (f"room{r}",)) for r in range(6) for _ in range(4)]
    grown = OnlineSpCoTMHP(K=2, L=2, max_K=16, max_L=16, seed=0).partial_fit(events)
    assert grown.state_.K > 2 and (grown.state_.n_k > 0).sum() == 6
    with pytest.warns(TruncationWarning, match="max_K"):
        OnlineSpCoTMHP(K=2, L=8, max_K=4, seed=0).partial_fit(events)


def test_bad_teaching_is_refused_and_changes_nothing(batch_dir):
    model = load_model(batch_dir)
    learner = OnlineSpCoTMHP(init_model=model).partial_fit([])
    before = {k: np.copy(v) for k, v in vars(learner.state_).items() if isinstance(v, np.ndarray)}
    wall = wall_point(model)
    bad = [
        ({"x": wall[0], "y": wall[1], "utterance": ALICE}, "in a wall"),
        ({"x": 1e4, "y": 0.0, "utterance": ALICE}, "off the map"),
        ({"x": 0.0, "y": 0.0, "utterance": "  ...  "}, "empty"),
        ({"x": 0.0, "y": 0.0, "utterance": "alice " * 2000}, "characters"),
        ({"x": float("nan"), "y": 0.0, "utterance": ALICE}, "not finite"),
        ({"x": "a", "y": 0.0, "utterance": ALICE}, "two numbers"),
    ]
    good = {"x": float(new_spot(model)[0]), "y": float(new_spot(model)[1]), "utterance": ALICE}
    for event, message in bad:
        with pytest.raises(TeachingError, match=message):
            learner.partial_fit([good, event])  # the good event before it is not learned either
    after = {k: v for k, v in vars(learner.state_).items() if isinstance(v, np.ndarray)}
    assert all(np.array_equal(before[k], after[k]) for k in before)


def _plan_end(model, words: str, start):
    planner, _ = planner_for(model)
    return np.asarray(planner.plan(f"go to {words}", start).path[-1])


@pytest.mark.parametrize("source", ["batch", "supervised"])
def test_a_name_taught_three_times_is_plannable(source, batch_dir, tmp_path):
    folder = batch_dir if source == "batch" else supervised_model_dir("3LDK_01", tmp_path / "s")
    model = load_model(folder)
    spot = new_spot(model)
    start = start_near(model)
    kitchen = _plan_end(model, "the kitchen", start)
    for _ in range(3):
        taught = teach(model, [{"x": spot[0], "y": spot[1], "utterance": ALICE}])
        model = taught.model
    assert taught.labels[-1] == "alice's room" and {"alice's", "room"} <= set(taught.place_words)
    assert np.linalg.norm(_plan_end(model, "alice's room", start) - spot) < 1.0
    assert np.linalg.norm(_plan_end(model, "the kitchen", start) - kitchen) < 0.5
    assert len(model.learner["arrays"]["place"]) >= 3


def test_learner_state_round_trips_through_the_folder(batch_dir, tmp_path):
    model = load_model(batch_dir)
    assert model.learner is not None
    taught = teach(model, [{"x": 0.0, "y": 0.5, "utterance": ALICE}])
    saved = load_model(save_model(taught.model, tmp_path / "t"))
    for name, value in taught.model.learner["arrays"].items():
        assert np.array_equal(saved.learner["arrays"][name], value), name
    again = teach(saved, [{"x": 0.0, "y": 0.5, "utterance": ALICE}])
    assert again.places == teach(taught.model, [{"x": 0.0, "y": 0.5, "utterance": ALICE}]).places
    assert np.allclose(OnlineSpCoTMHP(init_model=model).partial_fit([]).state_.n_lk, model.learner["arrays"]["n_lk"])


def test_cli_teach_updates_the_folder_and_refuses_other_folders(batch_dir, tmp_path):
    from typer.testing import CliRunner

    from spcotmhp.cli import app

    folder = save_model(load_model(batch_dir), tmp_path / "m")
    spot = new_spot(load_model(folder))
    runner = CliRunner()
    for _ in range(3):
        out = runner.invoke(app, ["teach", str(folder), ALICE, "--at", f"{spot[0]}", f"{spot[1]}"])
        assert out.exit_code == 0, out.output
    assert "'alice's room'" in out.output and "saved to" in out.output
    model = load_model(folder)
    assert np.linalg.norm(_plan_end(model, "alice's room", start_near(model)) - spot) < 1.0
    other = tmp_path / "data"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    out = runner.invoke(app, ["teach", str(other), ALICE, "--at", "0", "0"])
    assert out.exit_code != 0 and (other / "notes.txt").read_text() == "mine"


def test_http_teach_then_plan(batch_dir):
    from fastapi.testclient import TestClient

    from spcotmhp.server import create_app

    model = load_model(batch_dir)
    spot = [float(v) for v in new_spot(model)]
    client = TestClient(create_app({"home": batch_dir}), base_url="http://localhost")
    start = start_near(model)
    for _ in range(3):
        r = client.post("/teach", json={"utterance": ALICE, "x": spot[0], "y": spot[1]})
        assert r.status_code == 200, r.text
    assert r.json()["label"] == "alice's room" and "alice's" in r.json()["names"]
    plan = client.post("/plan", json={"instruction": "go to alice's room", "start": start}).json()
    assert np.linalg.norm(np.asarray(plan["path"][-1]) - spot) < 1.0
    wall = wall_point(model)
    r = client.post("/teach", json={"utterance": ALICE, "x": wall[0], "y": wall[1]})
    assert r.status_code == 422 and "wall" in r.json()["detail"] and r.json()["cause"] == "TeachingError"
    r = client.post("/teach", json={"utterance": "x" * 10_000, "x": spot[0], "y": spot[1]})
    assert r.status_code in (413, 422)
    assert json.loads(client.get("/models").text)["models"][0]["places"] == int(model.active_places.sum()) + 1


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"max_K": 10**8}, r"max_K must be an integer in \[1, 1000\], got 100000000"),
        ({"max_L": 10**8}, r"max_L must be an integer in \[1, 1000\], got 100000000"),
        ({"lag": 10**9}, r"lag must be an integer in \[0, 100000\], got 1000000000"),
        ({"rejuvenation": -1}, r"rejuvenation must be an integer in \[0, 100000\], got -1"),
        ({"split_merge": 2.5}, r"split_merge must be an integer in \[0, 100000\], got 2.5"),
    ],
)
def test_online_sizes_are_bounded(kwargs, message):
    """Audit items 4 and 5: the online learner's truncation caps and per-event work are bounded
    (spcotmhp/limits.py), refused before any state is built."""
    learner = OnlineSpCoTMHP(**kwargs)
    with pytest.raises(TeachingError, match=message):
        learner.partial_fit([TeachingEvent(0.0, 0.0, ("kitchen",))])
