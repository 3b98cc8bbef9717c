"""Exceptions raised for bad input. The CLI turns any of them into a one-line message and a non-zero exit."""

from __future__ import annotations


class SpcotmhpError(Exception):
    """Base class of every error the library raises on purpose (bad files, bad arguments, impossible plans)."""


class MapError(SpcotmhpError):
    """A ROS map_server YAML or image is missing, malformed or unsupported."""


class DatasetError(SpcotmhpError):
    """A dataset folder is missing a file, or a file has rows that do not parse."""


class ModelError(SpcotmhpError):
    """A model folder is missing, corrupt, or from an incompatible format version."""


class InstructionError(SpcotmhpError):
    """An instruction names no known place, or is empty."""


class PlanningError(SpcotmhpError):
    """No path exists that satisfies the instruction (unreachable goal, start in a wall, ...)."""
