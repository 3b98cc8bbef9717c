"""Nav2's interface types as spcotmhp uses them: nav2_msgs built from Nav2's own interface files, and their check.

The extra ros2 cannot install nav2_msgs as a wheel (none is published), so ``make nav2-msgs`` builds the four
interfaces spcotmhp needs (FollowPath, NavigateToPose, NavigateThroughPoses, SpeedLimit) from Nav2 Jazzy's files in
ros2/nav2_msgs/ into the venv (README.md there). A different nav2_msgs (another ROS distribution's, sourced from a
ROS install first on PYTHONPATH) would silently fail to talk to Nav2 Jazzy: its type hashes differ, and DDS peers
match only equal hashes. :func:`check_nav2_msgs` compares every hash with Nav2 Jazzy's (EXPECTED_HASHES).
``python -m spcotmhp.ros.nav2_types`` runs the check (the Makefile does after building).
"""

from __future__ import annotations

import sys
from types import ModuleType

from spcotmhp.errors import SpcotmhpError
from spcotmhp.ros.type_hash import compiled_type_hash

# RIHS01 hashes (the 64 hex digits after "RIHS01_") of every nav2_msgs type built here, as ROS 2 Jazzy's
# rosidl_generator_type_description 4.6.6 computes them (the generated share/nav2_msgs/*/*.json, "type_hashes") from
# Nav2's interface files at tag 1.3.13 (= the jazzy branch, f4108e5b1c2bce804a1aa0c7be6673a8eb4a1501). The message
# hashes were recomputed with a second implementation (rosbags' RIHS01, tests/ros/test_nav2_msgs.py); one of them
# (NavigateToPose_FeedbackMessage) appears in a public source file; no other published copy was found to cite
# (ros2/nav2_msgs/README.md). The hash covers field names and types only: comments and constants (Nav2 added
# FollowPath's CONTROLLER_TIMED_OUT during Jazzy) do not change it, so it holds for every Jazzy release since 1.3.0.
_TABLE = """
SpeedLimit 83d8e4e842559f4d9a988b19d31b162216ec738536389f98438d1a166f91845a
FollowPath 9d95513552fb578cfb933d7e0160273911269cbdf4b348f1acb87d8a903b13cf
FollowPath_Feedback 496acbe672234cdb70be4f93d28a22aabbf441958e2e1ff443a44a96e9f3185b
FollowPath_FeedbackMessage 3f4008700ba56ac4c82b01ef2b7fdd3fc18dc194399c48e5c43ebf8008b891d5
FollowPath_GetResult 8ab4c588c878f0e997316ec559f172bb56fc210b484c2f6b280d391d3bd6890f
FollowPath_GetResult_Event 15f7e6ff9bb7589196caf5e069a55d704ad6b5f30bbdc7f1e04f2367a0eb2d37
FollowPath_GetResult_Request 36e9a26a637063ba2692fde90de56d1eb7f9ba374908e14e3aec90c7466e1c30
FollowPath_GetResult_Response b5ec36b035c915310afffc3cb4941ce7c8ba34221c00ebfd8db911af5e381bde
FollowPath_Goal 7ec8732a3a001bf92b87db3989ef6984b1a4b9b9e62e166543ffa72344ecd194
FollowPath_Result 432bc8fc1c0de59f8181d00bf8dcc7d58e76cebcfd2de471361e62f468ad4428
FollowPath_SendGoal 5b662aee1159e1d7e7b5f8fef21f556b8bc67c818c730a68e18bb29b85f66946
FollowPath_SendGoal_Event e2ba77fc64cec73d10a7b7adaa1afdab9c17898c36383344c8da1341199ea735
FollowPath_SendGoal_Request a4dfc2a22f6a63df6bd1974e38e378ded55bfd959d0162bc3a52b85ce09cd2ab
FollowPath_SendGoal_Response 2c1d1ec5fc39c057ac9caca056b351a82fad6e395e92d0e5fa6c780de91a26bd
NavigateToPose a56dba8a3234a1215e610180dc703ae25bbf406dded8b54887891c9732857eab
NavigateToPose_Feedback 9ebc544c7d41bd8c6060b191bf9f5e4ddca6c2f61ee9e04fcb62ed5d67218a33
NavigateToPose_FeedbackMessage 9d1f6fa2eb975ce733b419ac2e97b134d8ff92b6478b6559feed9a50bdfd82b3
NavigateToPose_GetResult c407920357d566771e8882b4ef4d1f1a84ee922d609920ccd57faa6d6e391dc5
NavigateToPose_GetResult_Event a6afa5991dfffdcc45a1be7fe6d8996fbf3d209fafca2fa361039e4e0b0295db
NavigateToPose_GetResult_Request 106d3457cf0db4c4a8d3373bab3ff6aa8ba8ad99ae6392ce9784830a7d04ac93
NavigateToPose_GetResult_Response c59f178c377de5318919c00bdbf7884cb3b185acfdffceba6c9f161e0aa3cc81
NavigateToPose_Goal 22a9dffbd6733011220460bd52edbc7843c8fc86282d40bc7ad3ca176a9dec10
NavigateToPose_Result ddbff7fc6d1e51d774d5defdb8398a57cb23fa8709355002d676408bb4860b85
NavigateToPose_SendGoal a4fcb3bee1bf32e21a0e541a943b221aa0826996e2c98f079b47022b256f48b5
NavigateToPose_SendGoal_Event bdc94ccf5fcb7263afa245871959c3df011b278ce34242a2a4eef05819aeb84e
NavigateToPose_SendGoal_Request e9381f2acfe9fa8c4838a277d0cde28a93c483564827b9f13496b9c2092e4f09
NavigateToPose_SendGoal_Response 99f97fcbb07daf024df4b8c3f02f19ce7fa3183fcedfb76b8772a61a371a55fa
NavigateThroughPoses 4e680a34fd27772095da6ffdb32ae348adbc3d948248d38cf8d5ca3fc7a3a6c4
NavigateThroughPoses_Feedback 56e169557485ca861b100e2530069cdf208bdc47cbb5bd9e9e9b5f3719bddb61
NavigateThroughPoses_FeedbackMessage 073962415ad2a226b3de7245b142aeb414268a4d35ef1321ff2a484e2130e2b1
NavigateThroughPoses_GetResult fdc12773de81ce69f7eeb4366702ea757d792ab5068bc461ee3b1438e66c7b36
NavigateThroughPoses_GetResult_Event 494e93f5dc8d29604736bfed242c9301a46b7015841b0e3f43010abb498daa12
NavigateThroughPoses_GetResult_Request e228678211f043e10c8b6fce48a6c34825bdf4b61c635f7d3797f01bfd10c488
NavigateThroughPoses_GetResult_Response 893b3d0f909977d49752d27b5efc5aa0e0e1ac5e5fbd4db0b2a1cb42e1998a32
NavigateThroughPoses_Goal 156eb642033047f1737b2f01c87da02ab81e841a3c896bbfba9317db388d2d8e
NavigateThroughPoses_Result e64524990d7d2778a414b35a00cc98e45acfda9aaa3cf810d07340fcde324d67
NavigateThroughPoses_SendGoal 5a590fa8e9a32b7b9c838fdf5939a2fb8858d6cfd25bdf2f2e5f0f7bbb25f52b
NavigateThroughPoses_SendGoal_Event ce71b404cffcd84cdc8fd88aaba7166869ab839dbe056234c92292659050dfd5
NavigateThroughPoses_SendGoal_Request 3cfab113ccc3be41f05c8fc99f57df5d0e20b8350621d0bc843062f25e50f21b
NavigateThroughPoses_SendGoal_Response abd99696630c2a5a7f0ac05b3223a0debf4307e42bdba425c6304fa1e223d6f0
"""
EXPECTED_HASHES = {
    f"nav2_msgs/{'msg' if name == 'SpeedLimit' else 'action'}/{name}": digest
    for name, digest in (line.split() for line in _TABLE.strip().splitlines())
}
ACTIONS = ("FollowPath", "NavigateToPose", "NavigateThroughPoses")
BUILD_HINT = "build it with `make nav2-msgs` (ros2/nav2_msgs/README.md)"


class Nav2MsgsMissing(SpcotmhpError):
    """nav2_msgs cannot be imported (not built into this environment)."""


class Nav2MsgsMismatch(SpcotmhpError):
    """The importable nav2_msgs is not Nav2 Jazzy's: some type hash differs, so it would not talk to Nav2 Jazzy."""


def import_nav2_msgs() -> tuple[ModuleType, ModuleType]:
    """``(nav2_msgs.action, nav2_msgs.msg)``; Nav2MsgsMissing (naming how to build them) when they are absent."""
    try:
        import nav2_msgs.action
        import nav2_msgs.msg
    except ImportError as e:
        raise Nav2MsgsMissing(f"nav2_msgs is not importable ({e}); {BUILD_HINT}") from None
    return nav2_msgs.action, nav2_msgs.msg


def interface_classes() -> dict[str, type]:
    """Every type of EXPECTED_HASHES by its ROS name (``nav2_msgs/action/FollowPath_SendGoal_Request``, ...) mapped
    to its generated class: the actions, their goal/result/feedback, and the services and messages rosidl derives."""
    action, msg = import_nav2_msgs()
    found: dict[str, type] = {"nav2_msgs/msg/SpeedLimit": msg.SpeedLimit}
    for name in ACTIONS:
        cls = getattr(action, name)
        prefix = f"nav2_msgs/action/{name}"
        found[prefix] = cls
        for part in ("Goal", "Result", "Feedback"):
            found[f"{prefix}_{part}"] = getattr(cls, part)
        found[f"{prefix}_FeedbackMessage"] = cls.Impl.FeedbackMessage
        for service, impl in (("SendGoal", cls.Impl.SendGoalService), ("GetResult", cls.Impl.GetResultService)):
            found[f"{prefix}_{service}"] = impl
            for part in ("Request", "Response", "Event"):
                found[f"{prefix}_{service}_{part}"] = getattr(impl, part)
    return found


def check_nav2_msgs() -> int:
    """Compare the type hash of every nav2_msgs type built here with Nav2 Jazzy's; the number of types checked.
    Raises Nav2MsgsMissing or Nav2MsgsMismatch (naming every type that differs)."""
    classes = interface_classes()
    if set(classes) != set(EXPECTED_HASHES):
        missing = sorted(set(EXPECTED_HASHES) - set(classes))
        raise Nav2MsgsMismatch(f"nav2_msgs lacks {', '.join(missing)}; {BUILD_HINT}")
    differ = [name for name, cls in classes.items() if compiled_type_hash(cls) != "RIHS01_" + EXPECTED_HASHES[name]]
    if differ:
        where = import_nav2_msgs()[0].__file__
        raise Nav2MsgsMismatch(
            f"the nav2_msgs at {where} is not Nav2 Jazzy's: the type hashes of {', '.join(sorted(differ))} differ "
            f"(another ROS distribution's first on PYTHONPATH?); {BUILD_HINT}"
        )
    return len(classes)


def main() -> int:
    """Command line: check the built nav2_msgs, one line of result; exit status 1 on failure."""
    try:
        count = check_nav2_msgs()
    except SpcotmhpError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    print(f"nav2_msgs: the {count} type hashes equal Nav2 Jazzy's")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
