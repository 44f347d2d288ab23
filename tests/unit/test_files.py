"""Output folders: a writer owns only what it wrote; atomic writes."""

from __future__ import annotations

from pathlib import Path

import pytest

from drillfatigue.errors import InputError
from drillfatigue.files import MARKER, OutputFolder, atomic_output, atomic_write_text


def test_new_folder_is_claimed_and_marked(tmp_path: Path) -> None:
    out = OutputFolder(tmp_path / "run", "run")
    atomic_write_text(out.file("summary.json"), "{}")
    again = OutputFolder(tmp_path / "run", "run")
    assert again.owns("summary.json")
    assert (tmp_path / "run" / MARKER).is_file()


def test_folder_with_a_foreign_file_is_refused_and_kept(tmp_path: Path) -> None:
    (tmp_path / "mine.docx").write_text("user data")
    with pytest.raises(InputError, match="did not write"):
        OutputFolder(tmp_path, "run")
    with pytest.raises(InputError, match="did not write"):
        OutputFolder.check(tmp_path, "run")
    assert (tmp_path / "mine.docx").read_text() == "user data"
    assert not (tmp_path / MARKER).exists()


def test_other_kind_and_file_refused(tmp_path: Path) -> None:
    OutputFolder(tmp_path / "m", "model")
    with pytest.raises(InputError, match="model output, not a run"):
        OutputFolder(tmp_path / "m", "run")
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="is a file"):
        OutputFolder(tmp_path / "f", "run")


def test_remove_deletes_only_owned_files(tmp_path: Path) -> None:
    out = OutputFolder(tmp_path, "run")
    atomic_write_text(out.file("loads.parquet"), "a")
    (tmp_path / "loads.xlsx").write_text("user")  # added by the user later
    with pytest.raises(InputError, match="not written by drillfatigue"):
        out.file("loads.xlsx")
    out.remove(["loads.parquet", "loads.xlsx"])
    assert not (tmp_path / "loads.parquet").exists()
    assert (tmp_path / "loads.xlsx").read_text() == "user"


def test_atomic_output_leaves_nothing_on_error(tmp_path: Path) -> None:
    target = tmp_path / "a.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_output(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("boom")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_names_to_write_are_checked_before_the_folder_changes(tmp_path: Path) -> None:
    """A marked folder holding a user's file under a name the writer will write: both the
    check and the claim refuse it at once, and the marker and the files stay as they were."""
    d = tmp_path / "out"
    f = OutputFolder(d, "run")
    atomic_write_text(f.file("a.txt"), "ours")
    (d / "b.txt").write_text("mine")
    marker = (d / MARKER).read_text()
    for call in (lambda: OutputFolder.check(d, "run", names=["a.txt", "b.txt"]),
                 lambda: OutputFolder(d, "run", names=["a.txt", "b.txt"])):
        with pytest.raises(InputError, match="b.txt exists and was not written"):
            call()
        assert (d / MARKER).read_text() == marker
        assert (d / "a.txt").read_text() == "ours" and (d / "b.txt").read_text() == "mine"
    OutputFolder.check(d, "run", names=["a.txt", "c.txt"])  # its own and new names pass
    assert OutputFolder(d, "run", names=["a.txt", "c.txt"]).owns("a.txt")
