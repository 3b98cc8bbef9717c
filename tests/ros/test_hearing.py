"""Speech on the robot (spcotmhp.ros.hearing) and the tf wait (spcotmhp.ros.poses), through real rclpy messages:
`spcotmhp ros2 M --drive follow_path --tf-timeout 30` in a subprocess beside the stand-in Nav2, with discovery on
localhost and a domain of its own. The bundled say.wav ("go to the bedroom via the corridor", 16 kHz mono), sent
as PCM chunks on /spcotmhp/audio, is heard as the CLI hears it (the same hypotheses and weights), then planned and
driven; an utterance with no end message ends after the gap; an N-best JSON on /spcotmhp/hypotheses is planned
and driven, "stop" among them stops the robot; hostile audio and JSON give error statuses and the node keeps
serving. The recognition tests skip only without the extra speech (pocketsphinx); the rest without ros2."""

from __future__ import annotations

import json
import math
import os
import warnings
from types import SimpleNamespace

import numpy as np
import pytest

pytest.importorskip("rclpy")

from geometry_msgs.msg import PoseWithCovarianceStamped, TransformStamped  # noqa: E402
from std_msgs.msg import String, UInt8MultiArray  # noqa: E402

from spcotmhp.datasets.bundled import data_root, load_bundled  # noqa: E402
from spcotmhp.learning.supervised import fit_supervised  # noqa: E402
from spcotmhp.persistence.io import save_model  # noqa: E402
from spcotmhp.planning.query import MAX_HYPOTHESES  # noqa: E402
from spcotmhp.ros.hearing import AUDIO_QOS  # noqa: E402
from spcotmhp.ros.node import EVENTS, LATCHED  # noqa: E402
from spcotmhp.ros.tf_types import import_tf_message  # noqa: E402
from tests.ros.nav2_client import DriveClient, node_ready, standin, start_node, stop_node  # noqa: E402

DOMAIN = "101"  # not the other ROS tests' domains (1..100)
START = (-3.9, -3.5)  # the README's start in 3LDK_06 (the entrance)
SAY = data_root() / "examples" / "say.wav"  # "go to the bedroom via the corridor", 16 kHz mono 16-bit
CHUNK = 3200  # bytes: 0.1 s at 16 kHz, as an audio driver sends


class SpeechClient(DriveClient):
    """The stand-in's and the node's topics (DriveClient), and the speech topics."""

    def __init__(self, context) -> None:
        super().__init__(context)
        self.audio = self.node.create_publisher(UInt8MultiArray, "/spcotmhp/audio", AUDIO_QOS)
        self.hypotheses = self.node.create_publisher(String, "/spcotmhp/hypotheses", EVENTS)
        self.pose = self.node.create_publisher(PoseWithCovarianceStamped, "/amcl_pose", LATCHED)

    def send_audio(self, pcm: bytes, end: bool = True) -> int:
        """Publish ``pcm`` in CHUNK-byte messages (and the empty message that ends it); the status count before."""
        assert self.spin_until(lambda: self.audio.get_subscription_count() > 0)
        mark = len(self.status)
        for i in range(0, len(pcm), CHUNK):
            self.audio.publish(UInt8MultiArray(data=pcm[i : i + CHUNK]))
        if end:
            self.audio.publish(UInt8MultiArray(data=b""))
        return mark

    def send_hypotheses(self, text: str) -> int:
        assert self.spin_until(lambda: self.hypotheses.get_subscription_count() > 0)
        mark = len(self.status)
        self.hypotheses.publish(String(data=text))
        return mark

    def next_status(self, after: int, kind: str | None = None) -> dict:
        found = lambda: [s for s in self.status[after:] if kind is None or s.get("kind") == kind]  # noqa: E731
        assert self.spin_until(lambda: bool(found())), f"no {kind or 'status'} after {after}"
        return found()[0]


def pcm_of(path) -> bytes:
    from scipy.io import wavfile

    rate, x = wavfile.read(path)
    assert rate == 16_000 and x.dtype == np.int16 and x.ndim == 1
    return x.astype("<i2").tobytes()


@pytest.fixture(scope="module")
def robot(tmp_path_factory):
    root = tmp_path_factory.mktemp("hearing")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06"))
    folder = save_model(model, root / "model")
    args = ("--speed", "3.0", "--x", str(START[0]), "--y", str(START[1]))
    with standin(root, DOMAIN, *args, client_class=SpeechClient) as client:
        env = {k: os.environ[k] for k in ("ROS_AUTOMATIC_DISCOVERY_RANGE", "ROS_DOMAIN_ID", "ROS_LOG_DIR")}
        proc = start_node(folder, env, "follow_path", "--tf-timeout", "30")
        try:
            node_ready(client, proc)
            yield SimpleNamespace(client=client, proc=proc, model=model, folder=folder)
        finally:
            stop_node(proc)


@pytest.fixture(scope="module")
def ps():
    return pytest.importorskip("pocketsphinx", reason="pocketsphinx (extra 'speech') is not installed")


def _arrived(c: SpeechClient, after: int) -> None:
    assert c.spin_until(lambda: any(s["final"] for s in c.drive_events(after, "arrived")) or c.errors(after))
    assert not c.errors(after), c.errors(after)


def test_a_spoken_wav_is_heard_as_the_cli_hears_it_then_planned_and_driven(robot, ps):
    from spcotmhp.speech import recognise_for_model

    c = robot.client
    events0 = len(c.events)
    mark = c.send_audio(pcm_of(SAY))
    heard = c.next_status(mark, "heard")
    assert heard["ok"] and heard["source"] == "audio"
    cli = recognise_for_model(SAY, robot.model)  # the CLI's recogniser (spcotmhp plan --audio), same grammar
    assert [h["text"] for h in heard["hypotheses"]] == [t for t, _ in cli]
    assert [h["score"] for h in heard["hypotheses"]] == pytest.approx([w for _, w in cli])
    assert cli[0][0] == "go to the bedroom via corridor"  # what the CLI hears in it
    plan = c.next_status(mark, "plan")
    assert plan["instruction"] == cli[0][0] and [p["name"] for p in plan["places"] if p["role"] == "waypoint"] == [
        "corridor"
    ]
    assert plan["places"][-1]["name"] == "bedroom" and plan["places"][-1]["role"] == "goal"
    assert c.event("goal", events0)["event"] == "goal"  # driven: the stand-in accepted a FollowPath goal
    _arrived(c, mark)


def test_an_utterance_without_its_end_message_ends_after_the_gap(robot, ps):
    c = robot.client
    mark = c.send_audio(pcm_of(SAY), end=False)  # no empty message: the 1 s gap ends it
    heard = c.next_status(mark, "heard")
    assert heard["hypotheses"][0]["text"] == "go to the bedroom via corridor"
    _arrived(c, mark)


def test_an_n_best_list_on_hypotheses_is_planned_and_driven_and_stop_stops(robot):
    c = robot.client
    nbest = [{"text": "go to the kitchen", "score": 0.7}, {"text": "go to the kitten", "confidence": 0.3}]
    mark = c.send_hypotheses(json.dumps(nbest))
    heard = c.next_status(mark, "heard")
    assert heard["source"] == "hypotheses" and [h["text"] for h in heard["hypotheses"]] == [
        "go to the kitchen",
        "go to the kitten",
    ]
    plan = c.next_status(mark, "plan")
    assert plan["ok"] and plan["places"][-1]["name"] == "kitchen" and plan["instruction"] == "go to the kitchen"
    c.until_drive(mark, "progress")
    c.send_hypotheses(json.dumps([{"text": "stop", "score": 1.0}]))
    assert "stop" in c.until_drive(mark, "canceled")["reason"]


def test_hostile_audio_and_hypotheses_give_error_statuses(robot):
    c = robot.client
    cases = [
        (lambda: c.send_audio(bytes(CHUNK) + b"x"), "AudioError", "not whole 16-bit samples"),
        (lambda: c.send_audio(b"\x10\x00" * 400), "AudioError", "ms long"),  # 25 ms
        (lambda: c.send_audio(bytes(16_000)), "AudioError", "silent"),
        (lambda: c.send_hypotheses("go to the kitchen"), "MalformedInstruction", "not valid JSON"),
        (lambda: c.send_hypotheses('{"text": "go"}'), "MalformedInstruction", "must be a JSON list"),
        (lambda: c.send_hypotheses('[{"text": 3, "score": 1}]'), "MalformedInstruction", "entry 0"),
        (lambda: c.send_hypotheses('[{"text": "go to the bath", "score": "high"}]'), "MalformedInstruction", "score"),
        (lambda: c.send_hypotheses("[]"), "EmptyInstruction", "empty"),
        (lambda: c.send_hypotheses(json.dumps([{"text": "go", "score": 1}] * 10_000)), "InstructionTooLarge", ""),
        (lambda: c.send_hypotheses("[" * 50_000), "MalformedInstruction", "not valid JSON"),
        (lambda: c.send_hypotheses('[{"text": "go to the moon", "score": 1}]'), "UnknownPlaceWord", "moon"),
    ]
    for send, kind, words in cases:
        mark = send()
        status = c.next_status(mark, "error")  # the moon is heard first (a "heard" status), then not planned
        assert status["ok"] is False and kind in (status["type"], *_bases(status["type"])), status
        assert words in status["error"] and status["source"] in ("audio", "hypotheses"), status
    assert MAX_HYPOTHESES < 10_000


def test_an_over_long_utterance_is_refused_once_and_its_rest_dropped(robot):
    c = robot.client
    assert c.spin_until(lambda: c.audio.get_subscription_count() > 0)
    mark = len(c.status)
    second = (1000 * np.sin(np.arange(16_000) / 3)).astype("<i2").tobytes()
    for _ in range(62):  # 62 s with no end message (60 s is the limit), then its end
        c.audio.publish(UInt8MultiArray(data=second))
        c.spin_until(lambda: False, 0.005)
    c.audio.publish(UInt8MultiArray(data=b""))
    status = c.next_status(mark)
    assert status["type"] == "AudioError" and "longer than 60 s" in status["error"]
    c.spin_until(lambda: False, 2.0)  # the gap and the end pass: no other status for the dropped rest
    assert [s["type"] for s in c.status[mark:]] == ["AudioError"]
    assert robot.proc.poll() is None
    marks = c.tell("go to the bath")  # the node still serves
    assert c.next_status(marks[0], "plan")["ok"]
    _arrived(c, marks[0])


def test_a_pose_in_another_frame_waits_for_its_transform(robot):
    """--tf-timeout 30: a pose in late_odom (not heard yet) is held back, not refused: an instruction meanwhile
    is refused (NoValidPose, saying it waits); then map -> late_odom on /tf_static makes it the pose planned
    from. By hand: late_odom's origin at the entrance less 1 m in x, not turned; its (1, 0) is the entrance."""
    c = robot.client
    x0, y0 = c.where()  # the stand-in's pose, where the robot is (idle)
    msg = PoseWithCovarianceStamped()
    msg.header.frame_id = "late_odom"
    msg.pose.pose.position.x, msg.pose.pose.orientation.w = 1.0, 1.0
    assert c.spin_until(lambda: c.pose.get_subscription_count() > 0)
    c.pose.publish(msg)
    c.spin_until(lambda: False, 0.5)
    marks = c.tell("go to the kitchen")
    refused = c.next_status(marks[0])
    assert refused["type"] == "NoValidPose" and "waits up to 30 s" in refused["error"], refused
    tf_message = import_tf_message()
    static = c.node.create_publisher(tf_message, "/tf_static", LATCHED)
    ts = TransformStamped()
    ts.header.frame_id, ts.child_frame_id = "map", "late_odom"
    ts.transform.translation.x, ts.transform.translation.y = START[0] - 1.0, START[1]
    ts.transform.rotation.w = 1.0
    static.publish(tf_message(transforms=[ts]))
    for _ in range(100):  # until the node has heard it (discovery of the new publisher); not a timing check
        marks = c.tell("go to the kitchen")
        status = c.next_status(marks[0])
        if status["ok"]:
            break
        assert status["type"] == "NoValidPose" and "waits up to 30 s" in status["error"], status
        c.spin_until(lambda: False, 0.2)
    assert status["start"] == pytest.approx(START, abs=1e-3)  # the pose through tf, not the robot's
    assert math.dist(START, (x0, y0)) > 0.5  # (the robot stands elsewhere: at the bath, the test before's goal)
    _arrived(c, marks[0])
    c.node.destroy_publisher(static)


@pytest.mark.parametrize(
    ("option", "value", "said"),
    [("--audio-rate", "12345", "one of 8000"), ("--audio-gap", "0", "0.05"), ("--tf-timeout", "-1", "--tf-timeout")],
)
def test_bad_speech_and_tf_options_are_refused_in_one_line(robot, option, value, said):
    import subprocess

    from tests.ros.nav2_client import EXE

    done = subprocess.run([EXE, "ros2", str(robot.folder), option, value], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and said in done.stderr and "Traceback" not in done.stderr, done.stderr


def _bases(name: str) -> tuple[str, ...]:
    import spcotmhp.errors as errors

    cls = getattr(errors, name, None)
    return tuple(k.__name__ for k in cls.__mro__) if cls is not None else ()
