"""Output written completely or not at all: single files and whole output folders.

* :func:`write_file` writes one file through a temporary file in the same folder and a rename,
  so a reader never sees half a file and a failure leaves nothing behind.
* :class:`OutputFolder` collects a whole output (a simulation run, a reproduction) in a
  temporary folder beside the requested one, made before any work starts (so an unwritable
  place is an error up front), and renames it onto the requested folder only when everything
  is written. An existing folder is replaced only if it is empty or an earlier output of the
  same kind; anything else is left alone (an error).

Both give their files and folders the ordinary permissions of the user's umask (the
``tempfile`` functions they use make private ones).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from types import TracebackType

__all__ = ["OutputFolder", "write_file"]


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_file(path: str | Path, data: bytes | str) -> Path:
    """Write ``data`` (text as UTF-8) to ``path`` atomically; ``ValueError`` if its folder cannot be written."""
    path = Path(path)
    parent = path.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as error:
        raise ValueError(f"{path}: cannot write in {parent}: {error.strerror or error}") from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data.encode() if isinstance(data, str) else data)
            os.fchmod(handle.fileno(), 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


class OutputFolder:
    """``with OutputFolder(out, is_previous, kind) as tmp:`` write into ``tmp``; on success it becomes ``out``.

    ``is_previous(folder)`` says whether an existing non-empty ``out`` is an earlier output of this
    kind (then it is replaced); ``kind`` names that kind in the error otherwise. The checks and the
    temporary folder are made when the object is created, before any work: ``ValueError`` names the
    folder and what is wrong. On an error inside the ``with`` block the temporary folder is removed
    and ``out`` is left as it was.
    """

    def __init__(self, out: str | Path, is_previous: Callable[[Path], bool], kind: str) -> None:
        self.out = Path(out)
        if self.out.exists():
            if not self.out.is_dir():
                raise ValueError(f"--out {self.out}: exists and is not a folder")
            if any(self.out.iterdir()) and not is_previous(self.out):
                raise ValueError(f"--out {self.out}: exists and is not {kind}; give a new or empty folder")
        parent = self.out.absolute().parent
        try:
            parent.mkdir(parents=True, exist_ok=True)
            self.tmp = Path(tempfile.mkdtemp(dir=parent, prefix=f".{self.out.name}.", suffix=".tmp"))
            self.tmp.chmod(0o777 & ~_umask())
        except OSError as error:
            raise ValueError(f"--out {self.out}: cannot write in {parent}: {error.strerror or error}") from None

    def __enter__(self) -> Path:
        return self.tmp

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 traceback: TracebackType | None) -> None:
        if kind is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
            return
        old = None
        if self.out.exists():
            old = Path(tempfile.mkdtemp(dir=self.tmp.parent, prefix=f".{self.out.name}.", suffix=".old"))
            os.replace(self.out, old / "previous")
        try:
            os.replace(self.tmp, self.out)
        except OSError:
            if old is not None:
                os.replace(old / "previous", self.out)
            shutil.rmtree(self.tmp, ignore_errors=True)
            raise
        finally:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)
