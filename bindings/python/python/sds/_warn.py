"""The report's warnings as Python warnings (:class:`sds.SdsWarning`), raised by ``sds.score``,
``sds.compare`` and ``sds.merge`` at their caller's line: a notebook shows them, and
``warnings.simplefilter("error" | "ignore", sds.SdsWarning)`` makes them fatal or silent."""

from __future__ import annotations

import warnings
from typing import Any, Iterable

from ._sds import SdsWarning


def warn_each(messages: Iterable[Any]) -> None:
    """Warns each message as an :class:`SdsWarning`, attributed to the line that called the
    public function that called this (two frames up)."""
    for m in messages:
        warnings.warn(str(m), SdsWarning, stacklevel=3)
