"""Paths as the front ends take them: one type, one conversion (shared by score, watch, compare)."""

from __future__ import annotations

import os
from typing import List, Sequence, Union

PathLike = Union[str, "os.PathLike[str]"]
"""A path: a string or an ``os.PathLike`` (``pathlib.Path``)."""


def paths(results: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    """One path or several, as the list of strings the native module takes."""
    if isinstance(results, (str, os.PathLike)):
        return [os.fspath(results)]
    return [os.fspath(r) for r in results]
