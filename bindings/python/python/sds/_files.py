"""Writing a set of files the package names itself (``to_parquet``'s tables, the reports a
tracker copies into TensorBoard's log folder) as the ``sds`` command writes ``--tables`` and
``--figures``: through the library's write rules (``_sds.FileSet``; docs/RELIABILITY.md,
"Output"), never a copy of them:

- each file goes to a temporary file in its folder (created with ``O_EXCL | O_NOFOLLOW``),
  renamed over the name: a link planted at the name is refused, never followed, and so is
  anything but a regular file;
- a file replaced is kept as a hard-linked backup until the whole set is written; on an error
  (a full disk, Ctrl-C) the files written are removed, the replaced ones put back and the
  folders created removed: the set is written all or nothing.
"""

from __future__ import annotations

import os
from pathlib import Path
from types import TracebackType
from typing import BinaryIO, Callable, Optional, Type

from . import _sds


def refuse_unsafe(path: Path) -> bool:
    """Raises :class:`IoError` when ``path`` is a link or anything but a regular file; returns
    whether a regular file is there."""
    return _sds.refuse_unsafe(str(path))


class FileSet:
    """The files written into ``folder`` (created with its missing parents), all or nothing: a
    context manager that keeps them when its block ends normally and undoes them when it
    raises (any exception, ``KeyboardInterrupt`` included).

    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with FileSet(d) as out:
    ...     out.place(d / "a.txt", lambda f: f.write(b"hi"))
    >>> (d / "a.txt").read_bytes()
    b'hi'
    """

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self._set = _sds.FileSet(str(folder))

    def place(self, path: Path, write: Callable[[BinaryIO], object]) -> None:
        """Writes ``path`` (in this set's folder) through ``write``, which gets the temporary
        file open for writing, then renames it over ``path``."""

        def into(fd: int) -> None:
            # The library owns the descriptor (it syncs and closes it): write through a copy.
            with os.fdopen(os.dup(fd), "wb") as f:
                write(f)

        self._set.place(str(path), into)

    def commit(self) -> None:
        """Keeps what was written: drops the backups of the replaced files."""
        self._set.commit()

    def roll_back(self) -> None:
        """Removes what was created, puts back what was replaced, removes the folders created
        for the set when they are empty again."""
        self._set.roll_back()

    def __enter__(self) -> "FileSet":
        return self

    def __exit__(
        self,
        kind: Optional[Type[BaseException]],
        value: Optional[BaseException],
        tb: Optional[TracebackType],
    ) -> None:
        if kind is None:
            self.commit()
        else:
            self.roll_back()
