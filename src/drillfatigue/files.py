"""Writing files safely: atomic writes and output folders this package owns.

Two rules hold for every writer in the package:

* **Incomplete results never sit under a final name.** A file is written
  under a hidden temporary name in the same folder and renamed onto its
  final name only when complete (:func:`atomic_output` and the helpers built
  on it); a crash leaves the old file or none, never half of one.
* **A writer owns only what it wrote.** A folder that a command writes into
  carries a marker file, ``.drillfatigue.json``, naming the kind of output
  (``run``, ``fatigue``, ``model``, ``export``, ...) and listing the files
  this package wrote there (:class:`OutputFolder`). A writer accepts a new
  folder, an empty one, or one with a marker of its own kind; anything else
  is refused with a one-line :class:`~drillfatigue.errors.InputError`
  before any work is done. On a rewrite it replaces or removes only the
  files listed in the marker; a user's file beside them is never touched.
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import Any

from drillfatigue.errors import InputError

MARKER = ".drillfatigue.json"


@contextlib.contextmanager
def atomic_output(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; move it onto ``path`` on success.

    The temporary file keeps ``path``'s suffix (matplotlib and pandas pick the
    format from it) and gets the usual ``0o666 & ~umask`` permissions. On an
    exception it is removed and ``path`` is left untouched.
    """
    p = Path(path)
    folder = p.parent if str(p.parent) else Path(".")
    folder.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=f".tmp{p.suffix}", dir=folder)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield Path(tmp)
        os.replace(tmp, p)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def atomic_write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; returns ``Path(path)``."""
    with atomic_output(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def atomic_write_text(path: str | Path, text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically; returns ``Path(path)``."""
    return atomic_write_bytes(path, text.encode("utf-8"))


def atomic_write_json(path: str | Path, data: Any) -> Path:
    """Write ``data`` as indented JSON (trailing newline) atomically."""
    return atomic_write_text(path, json.dumps(data, indent=2) + "\n")


class OutputFolder:
    """A folder this package writes into, with its ownership marker.

    Parameters
    ----------
    path : path-like
        The folder. Created if missing.
    kind : str
        What the folder holds (``"run"``, ``"fatigue"``, ``"model"``, ...).
    option : str
        The name the user gave the folder by (``"--out"``), used in errors.
    names : iterable of str
        The files this writer will write there: one of them that exists and
        was not written by this package is refused here, before anything in
        the folder changes (otherwise :meth:`file` refuses it only when that
        file's turn comes, after earlier outputs were rewritten).

    Raises
    ------
    InputError
        ``path`` is a file, a non-empty folder without a marker of ``kind``, or
        holds a file of one of ``names`` that this package did not write.
    """

    def __init__(self, path: str | Path, kind: str, option: str = "--out",
                 names: Iterable[str] = ()) -> None:
        self.path = Path(path)
        self.kind = kind
        self.option = option
        self.owned: set[str] = set()
        allowed = f"a new or empty folder, or one written by drillfatigue as a {kind} folder"
        if self.path.exists() and not self.path.is_dir():
            raise InputError(option, f"{self.path} is a file, not a folder", allowed)
        if self.path.is_dir():
            marker = self.path / MARKER
            if marker.is_file():
                try:
                    info = json.loads(marker.read_text(encoding="utf-8"))
                    found_kind = info["kind"]
                    self.owned = {str(f) for f in info.get("files", [])}
                except (ValueError, KeyError, TypeError, UnicodeDecodeError) as exc:
                    raise InputError(option, f"{marker} is not a valid drillfatigue marker",
                                     allowed) from exc
                if found_kind != kind:
                    raise InputError(option, f"{self.path} holds a drillfatigue {found_kind} "
                                     f"output, not a {kind} output", allowed)
            elif any(self.path.iterdir()):
                raise InputError(option, f"{self.path} holds files drillfatigue did not write",
                                 allowed)
            _refuse_foreign(self.path, names, self.owned, option)
        self.path.mkdir(parents=True, exist_ok=True)
        self._save()

    @staticmethod
    def check(path: str | Path, kind: str, option: str = "--out",
              names: Iterable[str] = ()) -> None:
        """Raise :class:`InputError` if ``path`` could not be claimed for ``names``;
        write nothing."""
        p = Path(path)
        allowed = f"a new or empty folder, or one written by drillfatigue as a {kind} folder"
        if p.exists() and not p.is_dir():
            raise InputError(option, f"{p} is a file, not a folder", allowed)
        if not p.is_dir():
            return
        marker = p / MARKER
        if marker.is_file():
            try:
                info = json.loads(marker.read_text(encoding="utf-8"))
                found_kind = info["kind"]
                owned = {str(f) for f in info.get("files", [])}
            except (ValueError, KeyError, TypeError, UnicodeDecodeError) as exc:
                raise InputError(option, f"{marker} is not a valid drillfatigue marker",
                                 allowed) from exc
            if found_kind != kind:
                raise InputError(option, f"{p} holds a drillfatigue {found_kind} output, "
                                 f"not a {kind} output", allowed)
            _refuse_foreign(p, names, owned, option)
        elif any(p.iterdir()):
            raise InputError(option, f"{p} holds files drillfatigue did not write", allowed)

    def _save(self) -> None:
        atomic_write_json(self.path / MARKER, {"kind": self.kind,
                                               "files": sorted(self.owned)})

    def owns(self, name: str) -> bool:
        """Whether ``name`` (relative to the folder) was written by this package."""
        return name in self.owned

    def file(self, name: str) -> Path:
        """Path of ``name`` in the folder, recorded as owned (write it atomically).

        Raises :class:`InputError` if a file of that name exists that this
        package did not write.
        """
        p = self.path / name
        if (p.exists() or p.is_symlink()) and name not in self.owned:
            raise InputError(self.option, f"{p} exists and was not written by drillfatigue",
                             "a folder without foreign files of the names this command writes")
        if name not in self.owned:
            self.owned.add(name)
            self._save()
        return p

    def record(self, names: Iterable[str]) -> None:
        """Record files this package has just written here by other means (a library
        that writes a whole tree) as owned."""
        new = {str(n) for n in names} - self.owned - {MARKER}
        if new:
            self.owned |= new
            self._save()

    def remove(self, names: Iterable[str]) -> None:
        """Delete the listed files if this package wrote them; others are kept."""
        changed = False
        for name in names:
            if name in self.owned:
                (self.path / name).unlink(missing_ok=True)
                self.owned.discard(name)
                changed = True
        if changed:
            self._save()

    def remove_all_owned(self) -> None:
        """Delete every file this package wrote here (the marker stays)."""
        self.remove(sorted(self.owned))


def _refuse_foreign(folder: Path, names: Iterable[str], owned: set[str], option: str) -> None:
    """Raise :class:`InputError` for the first of ``names`` in ``folder`` not in ``owned``."""
    for name in names:
        f = folder / name
        if (f.exists() or f.is_symlink()) and name not in owned:
            raise InputError(option, f"{f} exists and was not written by drillfatigue",
                             "a folder without foreign files of the names this command writes")


def check_output_file(path: str | Path, option: str,
                      inputs: Iterable[tuple[str, str | Path | None]] = ()) -> None:
    """Raise :class:`InputError` if ``path`` cannot be written as one output file.

    An existing folder of that name is refused (it would be neither replaced
    nor written into), and so is a path that is one of the command's
    ``inputs`` (``(option, path)`` pairs; the same file by any name, a link
    included), or lies inside a folder among them (a model folder): the input
    would be lost. An existing file that is no input is replaced atomically
    when written: naming one output file is asking for it.
    """
    p = Path(path)
    if p.is_dir():
        raise InputError(option, f"{p} is a folder, not a file", "a file path")
    target = p.resolve()
    for in_option, in_path in inputs:
        if in_path is None:
            continue
        q = Path(in_path).resolve()
        if target == q or (p.exists() and q.exists() and os.path.samefile(p, q)):
            raise InputError(option, f"{p} is the {in_option} input", f"a path other than {in_option}")
        if q.is_dir() and target.is_relative_to(q):
            raise InputError(option, f"{p} lies inside the {in_option} folder",
                             f"a path outside {in_option}")
