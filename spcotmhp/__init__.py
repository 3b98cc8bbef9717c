"""SpCoTMHP: spatial concept-based topometric semantic mapping and hierarchical path planning.

Taniguchi, Ito and Taniguchi (2024), Front. Robot. AI 11:1291426.
"""

__version__ = "0.1.0"

from spcotmhp.numba_cache import cache_dir_default as _cache_dir_default

_cache_dir_default()
