"""Writing a set of files the package names itself (``to_parquet``'s tables, the reports a
tracker copies into TensorBoard's log folder) as the ``sds`` command writes ``--tables`` and
``--figures`` (docs/RELIABILITY.md, round 3 rules 2 and 3, round 4 finding 1):

- each file goes to a temporary file in its folder (created with ``O_EXCL | O_NOFOLLOW``),
  renamed over the name: a link planted at the name is refused, never followed, and so is
  anything but a regular file;
- a file replaced is kept as a hard-linked backup until the whole set is written; on an error
  (a full disk, Ctrl-C) the files written are removed, the replaced ones put back and the
  folders created removed: the set is written all or nothing.
"""

from __future__ import annotations

import itertools
import os
import stat
from pathlib import Path
from types import TracebackType
from typing import BinaryIO, Callable, List, Optional, Tuple, Type

from ._sds import IoError

_NEXT = itertools.count()


def _scratch(folder: Path, what: str) -> Path:
    """A unique name for a temporary or backup file beside the file it stands for."""
    return folder / f".sds-{os.getpid()}-{next(_NEXT)}.{what}"


def _describe(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "a special file"


def refuse_unsafe(path: Path) -> bool:
    """Raises :class:`IoError` when ``path`` is a link or anything but a regular file; returns
    whether a regular file is there."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return False
    if stat.S_ISLNK(st.st_mode):
        raise IoError(
            f"{path}: a symbolic link; sds never writes through a link at a name it chose "
            "(remove the link, or choose another folder)"
        )
    if not stat.S_ISREG(st.st_mode):
        raise IoError(f"{path}: {_describe(st.st_mode)}, not a regular file; sds writes only regular files")
    return True


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
        self._temps: List[Path] = []
        self._created: List[Path] = []
        self._replaced: List[Tuple[Path, Path]] = []
        self._dirs: List[Path] = []
        missing = []
        d = folder
        while str(d) not in ("", ".", "/") and not os.path.lexists(d):
            missing.append(d)
            d = d.parent
        folder.mkdir(parents=True, exist_ok=True)
        self._dirs = list(reversed(missing))

    def place(self, path: Path, write: Callable[[BinaryIO], object]) -> None:
        """Writes ``path`` (in this set's folder) through ``write``, which gets the temporary
        file open for writing, then renames it over ``path``."""
        existed = refuse_unsafe(path)
        tmp = _scratch(path.parent, "tmp")
        self._temps.append(tmp)
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
        with os.fdopen(os.open(tmp, flags, 0o666), "wb") as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        if existed:
            backup = _scratch(path.parent, "bak")
            try:
                os.link(path, backup)
            except OSError:
                os.rename(path, backup)
            self._replaced.append((path, backup))
        # Checked again just before the rename: a folder, FIFO or device that appeared at the
        # name is refused (a link there now is replaced by the rename, never followed).
        try:
            st = os.lstat(path)
            if not stat.S_ISREG(st.st_mode) and not stat.S_ISLNK(st.st_mode):
                raise IoError(f"{path}: became {_describe(st.st_mode)} while it was written; not replaced")
        except FileNotFoundError:
            pass
        os.rename(tmp, path)
        self._temps.remove(tmp)
        if not existed:
            self._created.append(path)

    def commit(self) -> None:
        """Keeps what was written: drops the backups of the replaced files."""
        for _, backup in self._replaced:
            try:
                os.remove(backup)
            except OSError:
                pass
        self._temps, self._created, self._replaced, self._dirs = [], [], [], []

    def roll_back(self) -> None:
        """Removes what was created, puts back what was replaced, removes the folders created
        for the set when they are empty again."""
        for p in self._temps + self._created[::-1]:
            try:
                os.remove(p)
            except OSError:
                pass
        for path, backup in self._replaced[::-1]:
            try:
                os.rename(backup, path)
            except OSError:
                pass
        for d in self._dirs[::-1]:
            try:
                os.rmdir(d)
            except OSError:
                pass
        self._temps, self._created, self._replaced, self._dirs = [], [], [], []

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
