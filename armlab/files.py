"""Output written completely or not at all: single files and whole output folders.

* :func:`write_file` writes one file through a temporary file in the same folder and a rename,
  so a reader never sees half a file and a failure leaves nothing behind.
* :class:`OutputFolder` collects a whole output (a simulation run, a reproduction) in a
  temporary folder beside the requested one, made before any work starts (so an unwritable
  place is an error up front), and renames it onto the requested folder only when everything
  is written. An existing output is replaced in one atomic step where the system can (Linux's
  ``renameat2(RENAME_EXCHANGE)`` swaps the two folders); elsewhere it is moved aside first, and a kill between
  the two renames is repaired by the next command on that folder (:func:`recover`), which also removes the
  temporaries of commands that were killed (their names carry the process id). An existing
  folder is replaced only if it is empty or an earlier output of the same kind; anything else
  is left alone (an error), and so are the working directory, a folder holding it, a file
  system's root and a mount point (they cannot be renamed).
* :func:`read_input` reads a user's input file with bounds: a regular file (a FIFO or a device such as
  ``/dev/zero`` could block or never end) of at most :data:`MAX_INPUT_BYTES`; :func:`read_json` parses
  one (segments, studies) with nesting within Python's recursion limit; one-line errors.
* :func:`stop_on_signals` turns SIGINT and SIGTERM into :class:`Interrupted` (a
  ``KeyboardInterrupt``) so that every ``with`` block unwinds and removes its temporaries; a
  signal arriving while a temporary is being renamed into place or removed waits until that is
  done; inside :func:`native_call` (a native parse that may never return) it ends the process at once.

Both give their files and folders the ordinary permissions of the user's umask (the
``tempfile`` functions they use make private ones).
"""

from __future__ import annotations

import csv
import ctypes
import errno
import functools
import io
import json
import math
import numbers
import os
import re
import shutil
import signal
import stat
import sys
import tempfile
import threading
import unicodedata
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from types import FrameType, TracebackType
from typing import Any

__all__ = [
    "MAX_INPUT_BYTES",
    "MAX_LABEL",
    "MAX_NAME",
    "Interrupted",
    "OutputFolder",
    "RecoveredWarning",
    "SignalState",
    "check_name",
    "csv_cell",
    "csv_rows",
    "csv_table",
    "csv_text",
    "file_path",
    "is_json_number",
    "json_number",
    "native_call",
    "read_input",
    "read_json",
    "recover",
    "signals_held",
    "stop_on_signals",
    "suffix_format",
    "write_csv",
    "write_file",
]

#: The largest input file read (bytes): far more than any segments file, study, DH table or URDF needs; a
#: bound on memory and time.
MAX_INPUT_BYTES = 10_000_000

#: The longest output folder name (bytes): file systems allow 255, and its temporary adds ``.PID.XXXXXXXX.tmp``.
MAX_NAME = 200

#: The signals that stop a command (Ctrl-C, and ``kill``'s default).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM arrived (inside :func:`stop_on_signals`); ``signum`` says which."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"stopped by {signal.Signals(signum).name}")
        self.signum = signum


class SignalState:
    """What :func:`stop_on_signals` saw: ``received`` is the last stop signal's number (0: none)."""

    def __init__(self) -> None:
        self.received = 0
        self.held = 0  # > 0 while a temporary is renamed into place or removed
        self.pending = 0  # a signal that arrived meanwhile


_STATE = SignalState()


def _importing(frame: FrameType | None) -> bool:
    """Whether ``frame`` runs inside an import (a module's code, or an extension module's initialisation)."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


#: The timers of :func:`_send_again` not yet fired: cancelled when :func:`stop_on_signals` is left (the signal is in
#: ``received`` already; sent after the handlers are restored, it would hit the interpreter's exit and print
#: "Exception ignored in: <module 'threading'> … KeyboardInterrupt").
_RESENDS: list[threading.Timer] = []


def _send_again(signum: int) -> None:
    """Send ``signum`` to this process again shortly (from a timer thread): it arrived where it cannot stop us."""
    timer = threading.Timer(0.05, os.kill, (os.getpid(), signum))
    timer.daemon = True  # never holds the interpreter's exit
    _RESENDS.append(timer)
    timer.start()


def _on_signal(signum: int, frame: FrameType | None) -> None:
    _STATE.received = signum
    if _STATE.held:
        _STATE.pending = signum
        return
    if _importing(frame):
        # An exception inside an extension module's initialisation (pydrake's) aborts the interpreter: the
        # signal is sent again shortly, until it arrives outside the import.
        _send_again(signum)
        return
    raise Interrupted(signum)


def _unraisable_hook(previous: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """``sys.unraisablehook`` that sends a stop signal again when its :class:`Interrupted` was raised where Python
    can only print it and go on (a weakref callback, a finalizer, a garbage collection), and else is ``previous``."""

    def hook(unraisable: Any) -> None:
        if isinstance(unraisable.exc_value, Interrupted):
            _send_again(unraisable.exc_value.signum)
        else:
            previous(unraisable)

    return hook


@contextmanager
def stop_on_signals() -> Iterator[SignalState]:
    """``with stop_on_signals() as state:`` SIGINT and SIGTERM raise :class:`Interrupted` in the main thread.

    Yields the :class:`SignalState` (``state.received``: the signal, for the exit code 128 + signal).
    A signal that arrives where Python cannot raise (an import, a weakref callback, a finalizer) is sent again
    shortly. The previous handlers are restored on leaving. Outside the main thread (where Python cannot set
    handlers) it changes nothing.
    """
    if threading.current_thread() is not threading.main_thread():
        yield SignalState()
        return
    _STATE.received = _STATE.pending = 0
    previous = {signum: signal.signal(signum, _on_signal) for signum in STOP_SIGNALS}
    previous_hook, sys.unraisablehook = sys.unraisablehook, _unraisable_hook(sys.unraisablehook)
    try:
        yield _STATE
    finally:
        while _RESENDS:
            _RESENDS.pop().cancel()
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        sys.unraisablehook = previous_hook


@contextmanager
def signals_held() -> Iterator[None]:
    """A stop signal arriving inside waits (raised on leaving): temporaries are renamed or removed whole.

    Only the main thread counts: Python runs signal handlers there, and other threads must not change its count."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    _STATE.held += 1
    try:
        yield
    finally:
        _STATE.held -= 1
        if not _STATE.held and _STATE.pending:
            signum, _STATE.pending = _STATE.pending, 0
            raise Interrupted(signum)


@contextmanager
def native_call() -> Iterator[None]:
    """Inside, a stop signal takes its default action (the process ends at once), where :func:`stop_on_signals`'
    handler is installed: for a native call that may not return soon (Drake's parser on a user's file), in which
    Python's handler could not run until it returned. Only for calls made while nothing is half-written (a
    temporary a killed command leaves is removed by the next one: :func:`recover`). Elsewhere (another thread,
    another handler: a library user's program) it changes nothing."""
    if threading.current_thread() is not threading.main_thread() or any(
            signal.getsignal(signum) is not _on_signal for signum in STOP_SIGNALS):
        yield
        return
    for signum in STOP_SIGNALS:
        signal.signal(signum, signal.SIG_DFL)
    try:
        yield
    finally:
        for signum in STOP_SIGNALS:
            signal.signal(signum, _on_signal)


def _remove(path: Path) -> None:
    """Remove a temporary file or folder, whatever state it is in."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


def _json_int(text: str) -> int | float:
    """A JSON integer: exact while a float holds it exactly, else a float (huge ones become inf, refused later)."""
    return int(text) if len(text.lstrip("-")) <= 15 else float(text)


def read_input(path: str | Path, where: str, max_bytes: int = MAX_INPUT_BYTES) -> bytes:
    """The bytes of a user's input file, if it is a regular file (not a device, pipe or folder, which could
    block or never end) of at most ``max_bytes``; else a one-line ``ValueError`` ``"WHERE: reason"``."""
    path = Path(path)
    try:
        if not stat.S_ISREG(path.stat().st_mode):
            raise ValueError(f"{where}: not a regular file")
        with path.open("rb") as handle:
            raw = handle.read(max_bytes + 1)
    except OSError as error:
        raise ValueError(f"{where}: {error.strerror or error}") from None
    if len(raw) > max_bytes:
        raise ValueError(f"{where}: larger than {max_bytes / 1e6:g} MB")
    return raw


def read_json(path: str | Path, what: str) -> Any:
    """The JSON in a user's file (:func:`read_input`); a one-line ``ValueError`` naming ``what`` (e.g.
    ``"--segments"``) and the file for anything else: no file, a device or pipe, too big, not UTF-8, not
    JSON, nested too deep. Integers too long for a float's precision are read as floats (``1e400`` as inf)."""
    raw = read_input(path, f"{what} {path}: cannot read it")
    try:
        return json.loads(raw.decode("utf-8"), parse_int=_json_int)
    except UnicodeDecodeError:
        raise ValueError(f"{what} {path}: cannot read it: it is not UTF-8 text") from None
    except RecursionError:
        raise ValueError(f"{what} {path}: not valid JSON: nested too deeply") from None
    except ValueError as error:
        raise ValueError(f"{what} {path}: not valid JSON: {error}") from None


#: The longest name a user's file may give a thing it lists (an obstacle, a load case, a motor): messages and
#: tables print it whole.
MAX_LABEL = 100


def check_name(raw: Any, what: str, limit: int = MAX_LABEL) -> str:
    """``raw`` if it is a name that prints on one line: text of at most ``limit`` characters without control
    characters (a newline, a tab, an escape; Unicode's line and paragraph separators). Else a one-line
    ``ValueError`` naming ``what`` and the value cut (:func:`armlab.values.shown`)."""
    # lazy: armlab.values loads numpy, which `armlab --help` (importing this module) does without (start-up time)
    from armlab.values import shown

    if not isinstance(raw, str):
        raise ValueError(f"{what} {shown(raw)} is not allowed: a name is text")
    if len(raw) > limit:  # not a bound: a count of characters
        raise ValueError(f"{what} {shown(raw)} ({len(raw):,} characters) is not allowed: at most {limit}")
    if any(unicodedata.category(c) in ("Cc", "Zl", "Zp") for c in raw):
        raise ValueError(f"{what} {shown(raw)} is not allowed: a name holds no control characters (newline, tab …)")
    return raw


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _make_folder(folder: Path) -> list[Path]:
    """Make ``folder`` with its missing parents; the folders made, deepest first (see :func:`_unmake`)."""
    made = [p for p in (folder, *folder.parents) if not p.exists()]
    folder.mkdir(parents=True, exist_ok=True)
    return made


def _unmake(made: list[Path]) -> None:
    """Remove the folders :func:`_make_folder` made, deepest first, as long as they are empty."""
    for folder in made:
        try:
            folder.rmdir()
        except OSError:  # not empty (someone else's files by now) or gone
            return


def file_path(path: str | Path) -> Path:
    """``path`` as the Path of a file to write; ``ValueError`` when its text ends with a slash (a folder's name:
    ``Path`` would drop the slash and the file would be written all the same)."""
    if isinstance(path, str) and path.endswith(("/", os.sep)):
        # lazy: armlab.values loads numpy, which `armlab --help` (importing this module) does without (start-up time)
        from armlab.values import shown

        raise ValueError(f"--out {shown(path)}: ends with '/', a folder; give a file name")
    return Path(path)


def suffix_format(path: str | Path, formats: Sequence[str]) -> str:
    """The format ``path``'s suffix names (lower case, no dot), one of ``formats``; ``ValueError`` for any other
    suffix or a folder's name (:func:`file_path`)."""
    fmt = file_path(path).suffix.lower().lstrip(".")
    if fmt not in formats:
        raise ValueError(f"--out {path}: the suffix must be one of {', '.join('.' + f for f in formats)}")
    return fmt


def write_file(path: str | Path, data: bytes | str) -> Path:
    """Write ``data`` (text as UTF-8) to ``path`` atomically; ``ValueError`` if its folder cannot be written
    or ``path`` names a folder (:func:`file_path`).

    Missing folders of ``path`` are made, and removed again if the file cannot be written."""
    path = file_path(path)
    parent = path.parent
    made: list[Path] = []
    with signals_held():
        try:
            made = _make_folder(parent)
            fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{path.name}.", suffix=".tmp")
        except OSError as error:
            _unmake(made)
            raise ValueError(f"{path}: cannot write in {parent}: {error.strerror or error}") from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data.encode() if isinstance(data, str) else data)
            os.fchmod(handle.fileno(), 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with signals_held():
            _remove(Path(tmp))
            _unmake(made)
        raise
    return path


def _check_replaceable(out: str | Path) -> Path:
    """``out`` as a Path if armlab may rename a folder onto it; ``ValueError`` for the working directory (``.``,
    ``''``), a folder holding it, a file system's root (``/``) or a mount point."""
    path = Path(out)
    size = len(os.fsencode(path.name))
    if size > MAX_NAME:
        # lazy: armlab.values loads numpy, which `armlab --help` (importing this module) does without (start-up time)
        from armlab.values import shown

        raise ValueError(f"--out {shown(str(out))}: its name is {size} bytes long; at most {MAX_NAME} (a file "
                         "system's 255 less room for the temporary folder's suffix)")
    where = path.resolve()
    cwd = Path.cwd().resolve()
    if where == cwd or where in cwd.parents:
        what = "the working directory" if where == cwd else f"a folder holding the working directory {cwd}"
        raise ValueError(f"--out {str(out)!r} is {what}, which cannot be replaced: give a new or empty folder "
                         "inside it, e.g. --out run")
    if where.parent == where or os.path.ismount(where):
        raise ValueError(f"--out {str(out)!r} is the root of a file system, which cannot be replaced: give a folder "
                         "inside it")
    return path


class RecoveredWarning(UserWarning):
    """An output folder put back from where an interrupted replacement had moved it."""


_AT_FDCWD = -100  # <fcntl.h>: paths relative to the working directory
_RENAME_EXCHANGE = 2  # <linux/fs.h>: renameat2 swaps the two paths


@functools.cache
def _renameat2() -> Any:
    """libc's ``renameat2`` (glibc 2.28+), or None where there is none."""
    try:
        return ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):
        return None


def _exchange(a: Path, b: Path) -> bool:
    """Swap the folders ``a`` and ``b`` in one atomic step; False where the system or file system cannot."""
    call = _renameat2()
    if call is None:
        return False
    if call(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    error = ctypes.get_errno()
    if error in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(error, os.strerror(error), str(b))


def _alive(pid: int) -> bool:
    """Whether process ``pid`` exists (someone else's counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _scratch(out: Path, suffix: str) -> Path:
    """A new empty hidden folder beside ``out``, ``.NAME.PID.XXXXXXXX.SUFFIX``: whose it is stays readable."""
    return Path(tempfile.mkdtemp(dir=out.absolute().parent, prefix=f".{out.name}.{os.getpid()}.",
                                 suffix=f".{suffix}"))


def recover(out: str | Path) -> Path | None:
    """Repair what killed commands left beside the output folder ``out``; the folder put back, if any.

    A missing ``out`` whose earlier output a dead process had moved aside (``.NAME.PID.X.old``, the first of the
    two renames of a replacement where no atomic swap exists) is put back, with a :class:`RecoveredWarning`;
    the other temporaries of dead processes (``.NAME.PID.X.tmp``, ``.old``) are removed. Those of live
    processes (another command writing the same output) are left alone.
    """
    out = Path(out)
    parent = out.absolute().parent
    pattern = re.compile(rf"\.{re.escape(out.name)}\.(\d+)\.[^./]+\.(tmp|old)")
    try:
        found = [(entry, match) for entry in parent.iterdir() if (match := pattern.fullmatch(entry.name))]
    except OSError:
        return None
    dead = [(entry, match[2]) for entry, match in found if not _alive(int(match[1]))]
    restored = None
    with signals_held():
        for entry, kind in sorted(dead, key=lambda item: item[0].stat().st_mtime, reverse=True):
            if kind == "old" and restored is None and not os.path.lexists(out) and entry.is_dir():
                os.replace(entry, out)
                restored = out
                warnings.warn(RecoveredWarning(f"{out}: put back the earlier output that an interrupted "
                                               f"replacement had moved to {entry.name}"), stacklevel=2)
            else:
                _remove(entry)
    return restored


class OutputFolder:
    """``with OutputFolder(out, is_previous, kind) as tmp:`` write into ``tmp``; on success it becomes ``out``.

    ``is_previous(folder)`` says whether an existing non-empty ``out`` is an earlier output of this
    kind (then it is replaced); ``kind`` names that kind in the error otherwise. The checks and the
    temporary folder are made when the object is created, before any work: ``ValueError`` names the
    folder and what is wrong. What killed commands left beside ``out`` is repaired first (:func:`recover`).
    On an error inside the ``with`` block the temporary folder is removed and ``out`` is left as it was.
    """

    def __init__(self, out: str | Path, is_previous: Callable[[Path], bool], kind: str) -> None:
        self.out = _check_replaceable(out)
        recover(self.out)
        if self.out.exists():
            if not self.out.is_dir():
                raise ValueError(f"--out {self.out}: exists and is not a folder")
            if any(self.out.iterdir()) and not is_previous(self.out):
                raise ValueError(f"--out {self.out}: exists and is not {kind}; give a new or empty folder")
        parent = self.out.absolute().parent
        self._made: list[Path] = []  # the missing parents made for it, removed again if the output fails
        with signals_held():
            try:
                self._made = _make_folder(parent)
                self.tmp = _scratch(self.out, "tmp")
            except OSError as error:
                _unmake(self._made)
                raise ValueError(f"--out {self.out}: cannot write in {parent}: {error.strerror or error}") from None
            try:
                self.tmp.chmod(0o777 & ~_umask())
            except BaseException:
                _remove(self.tmp)
                _unmake(self._made)
                raise

    def __enter__(self) -> Path:
        return self.tmp

    def __exit__(self, kind: type[BaseException] | None, value: BaseException | None,
                 traceback: TracebackType | None) -> None:
        with signals_held():
            if kind is not None:
                _remove(self.tmp)
                _unmake(self._made)
                return
            try:
                self._commit()
            except BaseException:
                _unmake(self._made)
                raise

    def _commit(self) -> None:
        """Put the temporary folder at ``out``: a rename, or an atomic swap with an existing ``out`` (then the
        earlier output, now at the temporary's name, is removed); where no swap exists, ``out`` is moved aside
        to ``.NAME.PID.X.old`` first (and back on failure; after a kill, by the next :func:`recover`)."""
        old = None
        try:
            if not self.out.exists():
                os.replace(self.tmp, self.out)
            elif not _exchange(self.tmp, self.out):
                old = _scratch(self.out, "old")
                os.replace(self.out, old)
                try:
                    os.replace(self.tmp, self.out)
                except OSError:
                    os.replace(old, self.out)
                    raise
        except OSError as error:
            raise ValueError(f"--out {self.out}: cannot put the output in place: {error.strerror or error}") from None
        finally:
            _remove(self.tmp)
            if old is not None:
                _remove(old)


def csv_cell(value: Any) -> str:
    """One CSV cell: a number as plain decimal text (full precision; numpy scalars too), ``None`` empty."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value) + 0.0)  # + 0.0: no "-0.0"
    raise ValueError(f"CSV cell {value!r} ({type(value).__name__}) is not allowed: a number, a string or None")


def csv_rows(lines: Iterable[str], where: str) -> list[list[str]]:
    """Every record (a list of cells, as text) of a user's CSV text ``lines``; a one-line ``ValueError`` starting
    with ``where`` for text CSV cannot read (a cell over csv's 131072-character limit)."""
    try:
        return list(csv.reader(lines))
    except csv.Error as error:
        raise ValueError(f"{where} cannot be read as CSV: {error}: a cell holds one number") from None


def csv_table(lines: Iterable[str], where: str) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """A user's CSV table: its header's names (stripped; the empty ones at its end, a spreadsheet's trailing commas,
    dropped; ``[]`` for no header) and its rows, each with its number (1 the row after the header; blank and
    whitespace-only ones are no rows) and its cells without the empty ones past the header's (trailing commas).
    ``ValueError`` starting with ``where`` for text CSV cannot read (:func:`csv_rows`)."""
    records = csv_rows(lines, where)
    header = [name.strip() for name in records[0]] if records else []
    rows = [(number, cells) for number, cells in enumerate(records[1:], start=1) if any(c.strip() for c in cells)]
    while header and not header[-1]:
        header.pop()
    for _, cells in rows:
        while len(cells) > len(header) and not cells[-1].strip():
            cells.pop()
    return header, rows


def csv_text(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A CSV file's text: the header row and one line per row, cells by :func:`csv_cell`."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(headers)
    writer.writerows([[csv_cell(v) for v in row] for row in rows])
    return buffer.getvalue()


def write_csv(path: str | Path, headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> Path:
    """Write :func:`csv_text` to ``path`` atomically (:func:`write_file`)."""
    return write_file(path, csv_text(headers, rows))


def is_json_number(raw: Any) -> bool:
    """True for a JSON number (an int or float, not a bool)."""
    return isinstance(raw, (int, float)) and not isinstance(raw, bool)


def json_number(raw: Any, name: str) -> float:
    """A number read from a user's JSON (:func:`read_json`), finite; ``ValueError`` naming ``name`` otherwise."""
    if not is_json_number(raw) or not math.isfinite(raw):
        raise ValueError(f"{name} = {json.dumps(raw)} must be a finite number")
    return float(raw)
