"""What every front end passes to the native module: paths, and the options of a scored run
(one definition for ``sds.score``, ``sds.watch`` and ``sds.compare``, as ``RunKwargs`` in Rust)."""

from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from ._sds import ConfigError

PathLike = Union[str, "os.PathLike[str]"]
"""A path: a string or an ``os.PathLike`` (``pathlib.Path``)."""


def paths(results: Union[PathLike, Sequence[PathLike]]) -> List[str]:
    """One path or several, as the list of strings the native module takes."""
    if isinstance(results, (str, os.PathLike)):
        return [os.fspath(results)]
    return [os.fspath(r) for r in results]


def strings(option: str, values: Sequence[str]) -> List[str]:
    """A list of strings; one string is refused (it would read as a list of characters)."""
    if isinstance(values, str):
        raise ConfigError(f"{option}={values!r}: expected a list, e.g. [{values!r}]")
    return [str(v) for v in values]


def run_options(
    *,
    profile: str,
    duplicates: Optional[str],
    expected_routes: Optional[int],
    allow_missing_telemetry: bool,
    settings: Optional[Mapping[str, Union[str, int, float, bool]]],
    jobs: Optional[int],
    protocols: Optional[Sequence[str]],
    route_subset: Optional[str] = None,
) -> Dict[str, Any]:
    """The options every scored run takes (Rust's ``RunKwargs``); ``protocols`` as one string
    is refused (it would read as a list of characters)."""
    if isinstance(protocols, str):
        raise ConfigError(
            f"protocols={protocols!r}: expected a list of ids, e.g. ['lb2.1'] or ['all']"
        )
    return {
        "profile": profile,
        "duplicates": duplicates,
        "expected_routes": None if expected_routes is None else int(expected_routes),
        "allow_missing_telemetry": allow_missing_telemetry,
        "settings": settings,
        "jobs": None if jobs is None else int(jobs),
        "protocols": None if protocols is None else list(protocols),
        "route_subset": route_subset,
    }
