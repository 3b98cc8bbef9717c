"""Dataset folders: loading, validation and the bundled real data."""

from spcotmhp.datasets.bundled import bundled_path, list_bundled, load_bundled
from spcotmhp.datasets.dataset import Dataset
from spcotmhp.datasets.loader import DatasetWarning, features_to_counts, load_dataset
from spcotmhp.datasets.synthetic import (
    generate_environment,
    generate_floor_plan,
    teaching_walk,
    write_dataset,
)

__all__ = [
    "Dataset",
    "DatasetWarning",
    "bundled_path",
    "features_to_counts",
    "generate_environment",
    "generate_floor_plan",
    "list_bundled",
    "load_bundled",
    "load_dataset",
    "teaching_walk",
    "write_dataset",
]
