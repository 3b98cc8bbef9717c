"""The RIHS01 type hash compiled into a generated ROS 2 interface type (ROS 2 Jazzy, REP 2016).

Every Jazzy type support carries a function returning the hash of its type description; DDS peers exchange it on
discovery, and two ends of a topic, service or action whose hashes differ do not talk. rclpy does not expose it for a
type, so it is read here through the type support that rclpy itself loads (the class's ``_TYPE_SUPPORT`` capsule
holding a C ``rosidl_message/service/action_type_support_t``). Used to check that the nav2_msgs built from Nav2's
interface files (ros2/nav2_msgs/) are the ones a Nav2 Jazzy install speaks.
"""

from __future__ import annotations

import ctypes
from typing import Any

from spcotmhp.errors import SpcotmhpError

HASH_SIZE = 32  # ROSIDL_TYPE_HASH_SIZE: a SHA-256 digest


class TypeHashUnavailable(SpcotmhpError):
    """The type's support carries no type hash (not a generated ROS 2 Jazzy type, or its support failed to load)."""


class _TypeHash(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint8), ("value", ctypes.c_uint8 * HASH_SIZE)]


_GetHash = ctypes.CFUNCTYPE(ctypes.POINTER(_TypeHash), ctypes.c_void_p)


def _slot(count: int) -> list[tuple[str, Any]]:
    return [(f"p{i}", ctypes.c_void_p) for i in range(count)]


class _MessageSupport(ctypes.Structure):  # rosidl_message_type_support_t: identifier, data, func, then the hash
    _fields_ = [*_slot(3), ("get_type_hash", ctypes.c_void_p)]


class _ServiceSupport(ctypes.Structure):  # rosidl_service_type_support_t: 8 members before the hash function
    _fields_ = [*_slot(8), ("get_type_hash", ctypes.c_void_p)]


class _ActionSupport(ctypes.Structure):  # rosidl_action_type_support_t: 5 member supports before the hash function
    _fields_ = [*_slot(5), ("get_type_hash", ctypes.c_void_p)]


_capsule_name = ctypes.pythonapi.PyCapsule_GetName
_capsule_name.restype = ctypes.c_char_p
_capsule_name.argtypes = [ctypes.py_object]
_capsule_pointer = ctypes.pythonapi.PyCapsule_GetPointer
_capsule_pointer.restype = ctypes.c_void_p
_capsule_pointer.argtypes = [ctypes.py_object, ctypes.c_char_p]


def compiled_type_hash(interface: type) -> str:
    """``RIHS01_<64 hex digits>`` of a generated message, service or action class, as its type support reports it
    (the hash sent on the wire). Raises TypeHashUnavailable for a class without a loaded Jazzy type support."""
    meta = type(interface)
    if getattr(meta, "_TYPE_SUPPORT", None) is None and hasattr(meta, "__import_type_support__"):
        meta.__import_type_support__()
    capsule = getattr(meta, "_TYPE_SUPPORT", None)
    if capsule is None:
        raise TypeHashUnavailable(f"{interface!r} has no ROS 2 type support (not a generated interface type)")
    if hasattr(interface, "Impl"):  # an action: its class names its goal, result and feedback
        layout: type[ctypes.Structure] = _ActionSupport
    elif hasattr(interface, "Request") and hasattr(interface, "Response"):
        layout = _ServiceSupport
    else:
        layout = _MessageSupport
    address = _capsule_pointer(capsule, _capsule_name(capsule))
    support = layout.from_address(address)
    if not support.get_type_hash:
        raise TypeHashUnavailable(f"{interface!r}: its type support has no type hash (built before ROS 2 Iron?)")
    found = _GetHash(support.get_type_hash)(address).contents
    if found.version != 1:
        raise TypeHashUnavailable(f"{interface!r}: type hash version {found.version}, only RIHS01 is known")
    return "RIHS01_" + bytes(found.value).hex()
