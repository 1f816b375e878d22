"""The path type every function of the package takes (``sds.PathLike``)."""

from __future__ import annotations

import os
from typing import Union

PathLike = Union[str, "os.PathLike[str]"]
"""A path: a string or an ``os.PathLike`` (``pathlib.Path``)."""
