"""The package's file sets (`sds._files`, used by `sds.to_parquet` and `sds.log`) are the
library's write rules (issue 48 item 1: one set of write rules), not a Python copy: the same
refusals in the same words as the `sds` command, the same all-or-nothing."""

from __future__ import annotations

import os
from pathlib import Path
from typing import BinaryIO

import pytest

import sds
from sds import _files


def test_i48_1_a_folder_at_a_chosen_name_is_refused_in_the_commands_words(tmp_path: Path) -> None:
    """A folder planted at a name the package chose is refused as `sds score --tables` refuses
    it, in the library's words (`a directory, not a regular file`; the Python copy said `a
    folder`), and a set meeting it writes nothing."""
    out = tmp_path / "tables"
    out.mkdir()
    (out / "events.parquet").mkdir()
    with pytest.raises(sds.IoError, match=r"events\.parquet: a directory, not a regular file; sds writes only regular files"):
        _files.refuse_unsafe(out / "events.parquet")
    os.mkfifo(out / "frames.parquet")
    with pytest.raises(sds.IoError, match=r"frames\.parquet: a FIFO"):
        with _files.FileSet(out) as files:
            files.place(out / "routes.parquet", lambda f: f.write(b"r"))
            files.place(out / "frames.parquet", lambda f: f.write(b"f"))
    assert sorted(p.name for p in out.iterdir()) == ["events.parquet", "frames.parquet"]


def test_i48_1_a_writers_exception_is_raised_as_is_and_the_set_undone(tmp_path: Path) -> None:
    """An exception of the writer (here `KeyboardInterrupt`, as Ctrl-C raises it) reaches the
    caller unchanged; the file replaced is put back, the file and the folders created are
    removed, and no temporary or backup file is left."""
    out = tmp_path / "a" / "b"
    keep = tmp_path / "keep.txt"
    keep.write_bytes(b"before")

    def interrupted(f: BinaryIO) -> None:
        f.write(b"half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        with _files.FileSet(out) as files:
            files.place(out / "routes.parquet", lambda f: f.write(b"new"))
            files.place(keep, lambda f: f.write(b"after"))
            files.place(out / "events.parquet", interrupted)
    assert keep.read_bytes() == b"before"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.txt"]
