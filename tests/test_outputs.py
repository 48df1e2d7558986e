"""The output rule of every command (``silcount.atomic``): missing folders are created, a path that cannot be
written is one line naming it with exit 3 and no traceback, and files get the mode ``open()`` gives them.

Tests run as root here, where a chmod'ed folder stops nothing, so the unwritable paths are ones that stop
root too: a file in ``/proc`` (no such file can be created: ENOENT), a file in ``/sys`` (EACCES), a folder
where a file goes, a file where a folder goes.  The expected modes come from ``open()`` itself, in the
same folder under the same umask.
"""

from __future__ import annotations

import errno
import os
import re
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from common import run_cli, shared_scenes
from meshfiles import tetra_bytes, write

from silcount.atomic import atomic_path, check_writable, write_text
from silcount.cli import figures as figures_cmd
from silcount.cli import report as report_cmd
from silcount.errors import UnwritableOutput

DATA = Path(__file__).resolve().parent.parent / "data"


def scene() -> str:
    return str(shared_scenes() / "cube_on_floor.json")


def sys_refuses_root() -> bool:
    try:
        Path("/sys/silcount-probe.json").touch()
    except OSError as exc:
        return exc.errno in (errno.EACCES, errno.EPERM)
    Path("/sys/silcount-probe.json").unlink()
    return False


# ---- modes -----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002, 0o027])
def test_written_files_get_the_mode_open_gives(tmp_path, mask):
    old = os.umask(mask)
    try:
        with open(tmp_path / "by_open.txt", "w") as fh:  # the oracle: what open() gives under this umask
            fh.write("x")
        write_text(tmp_path / "by_silcount.txt", "x")
    finally:
        os.umask(old)
    want = stat.S_IMODE((tmp_path / "by_open.txt").stat().st_mode)
    assert want == 0o666 & ~mask
    assert stat.S_IMODE((tmp_path / "by_silcount.txt").stat().st_mode) == want


# ---- the library's rule ------------------------------------------------------------------------------------
def test_missing_folders_are_created(tmp_path):
    target = tmp_path / "a" / "b" / "c.txt"
    assert write_text(target, "hello") == target and target.read_text() == "hello"
    assert check_writable(tmp_path / "x" / "y", folder=True).is_dir()
    assert check_writable(tmp_path / "p" / "q.json") and (tmp_path / "p").is_dir()
    assert list((tmp_path / "p").iterdir()) == []  # the probe is gone


def unwritable_cases(tmp_path: Path) -> dict[str, tuple[Path, str]]:
    (tmp_path / "dir").mkdir(exist_ok=True)
    (tmp_path / "file.txt").write_text("x")
    cases = {
        "in /proc": (Path("/proc/silcount-test.json"), "No such file or directory"),
        "a directory": (tmp_path / "dir", "Is a directory"),
        "under a file": (tmp_path / "file.txt" / "a.json", re.escape(f"{tmp_path}/file.txt is a file, not a folder")),
    }
    if sys_refuses_root():
        cases["in /sys"] = (Path("/sys/silcount-test.json"), "Permission denied|Operation not permitted")
    return cases


def test_unwritable_paths_are_one_error_naming_them(tmp_path):
    for path, reason in unwritable_cases(tmp_path).values():
        for check in (write_text, check_writable):
            with pytest.raises(UnwritableOutput) as caught:
                check(path, "x") if check is write_text else check(path)
            assert str(path) in str(caught.value)
            assert re.search(reason, str(caught.value)) and caught.value.exit_code == 3


def test_a_failed_write_is_one_error_and_leaves_nothing(tmp_path):
    target = tmp_path / "a.txt"
    target.write_text("old")
    with pytest.raises(UnwritableOutput, match=r"a\.txt: No space left on device"):
        with atomic_path(target) as tmp:
            tmp.write_text("half")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))  # what a full disk raises in the write
    assert target.read_text() == "old" and [p.name for p in tmp_path.iterdir()] == ["a.txt"]


# ---- every command that writes ---------------------------------------------------------------------------
def commands(tmp_path: Path, out: Path) -> dict[str, list[str]]:
    """Each writing command with ``out`` as its output path (a file for audit and render, else a folder)."""
    mesh = write(tmp_path, "tetra.obj", tetra_bytes("obj"))
    return {
        "audit": ["audit", str(mesh), "--light", "0,0,5", "--detectors", "reference", "--out", str(out)],
        "audit all": ["audit", "--random-lights", "1", "--detectors", "reference", "--out", str(out)],
        "render": ["render", scene(), "--method", "raycast", "--out", str(out)],
        "render --coverage": [
            "render",
            scene(),
            "--method",
            "raycast",
            "--out",
            str(tmp_path / "m.png"),
            "--coverage",
            str(out),
        ],  # fmt: skip
        "render --image": [
            "render",
            scene(),
            "--method",
            "raycast",
            "--out",
            str(tmp_path / "m.png"),
            "--image",
            str(out),
        ],  # fmt: skip
        "report": ["report", "--out", str(out)],
        "tables": ["tables", "--out", str(out)],
        "figures": ["figures", "--out", str(out)],
        "corpus": [
            "corpus",
            str(mesh),
            "--lights",
            "1",
            "--no-cache",
            "--no-time",
            "--scheduler",
            "threads",
            "--detectors",
            "reference",
            "--quiet",
            "--out",
            str(out),
        ],  # fmt: skip
        "calibrate": ["calibrate", "--timings", str(tmp_path / "missing.csv"), "--out", str(out)],
        "calibrate --measure": ["calibrate", "--measure", "--out", str(out)],
    }


FOLDER_OUTPUTS = {"audit all", "report", "tables", "figures", "corpus", "calibrate", "calibrate --measure"}


@pytest.mark.parametrize("case", ["in /proc", "a directory", "under a file", "in /sys"])
def test_every_command_refuses_an_unwritable_out_at_once_in_one_line(tmp_path, case):
    cases = unwritable_cases(tmp_path)
    if case not in cases:
        pytest.skip("/sys accepts new files here")
    path, reason = cases[case]
    for name, argv in commands(tmp_path, path).items():
        if name in FOLDER_OUTPUTS and case == "a directory":
            continue  # a directory is what these want
        rc, out, err = run_cli(*argv)
        assert rc == 3, (name, rc, err)
        assert err.count("\n") == 1 and re.search(reason, err) and "Traceback" not in err, (name, err)
        assert err.startswith(f"silcount {argv[0]}: error: cannot "), (name, err)


def test_folder_outputs_refuse_a_file_in_their_place(tmp_path):
    (tmp_path / "taken").write_text("x")
    for name, argv in commands(tmp_path, tmp_path / "taken").items():
        if name in FOLDER_OUTPUTS:
            rc, _, err = run_cli(*argv)
            assert rc == 3 and "taken is a file, not a folder" in err, (name, err)
    assert (tmp_path / "taken").read_text() == "x"


def test_every_command_creates_the_missing_folders_of_its_output(tmp_path, monkeypatch):
    # the expensive parts are replaced by small ones: what is tested is each command's handling of --out
    # (calibrate's is tests/test_calibrate.py's test_cli_reuses_a_timings_file)
    import silcount.papers.figures as paper_figures
    import silcount.papers.tables as paper_tables

    monkeypatch.setattr(report_cmd, "report_meshes", lambda: ("tetrahedron",))
    monkeypatch.setattr(report_cmd, "PARTS", ())
    monkeypatch.setattr(figures_cmd, "PARTS", ())
    monkeypatch.setattr(paper_figures, "PARTS", {"table": lambda d: [write_text(d / "t.txt", "t")]})
    monkeypatch.setattr(paper_tables, "tables_frame", lambda papers=None: None)
    monkeypatch.setattr(paper_tables, "RENDER", {f: (lambda df: "t\n") for f in paper_tables.FORMATS})
    written = {  # the command's --out below tmp_path/new, a file it then writes there
        "audit": ("a.json", "a.json"),
        "audit all": ("all", "all/tetrahedron.txt"),
        "render": ("m.png", "m.png"),
        "render --coverage": ("c.png", "c.png"),
        "render --image": ("i.png", "i.png"),
        "report": ("rep", "rep/audit/tetrahedron.json"),
        "tables": ("tab", "tab/tables.md"),
        "figures": ("fig", "fig/t.txt"),
        "corpus": ("cor", "cor/meshes.csv"),
    }
    for name, (out, target) in written.items():
        shutil.rmtree(tmp_path / "new", ignore_errors=True)
        rc, _, err = run_cli(*commands(tmp_path, tmp_path / "new" / "deeper" / out)[name])
        assert rc == 0 and (tmp_path / "new" / "deeper" / target).is_file(), (name, err)


def test_a_real_process_prints_one_line_for_a_bad_out(tmp_path):
    mesh = write(tmp_path, "tetra.obj", tetra_bytes("obj"))
    for out in ("/proc/silcount-test.json", str(tmp_path)):
        proc = subprocess.run(
            [sys.executable, "-m", "silcount.cli.main", "audit", str(mesh), "--light", "0,0,5", "--out", out],
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 3 and proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
        assert out in proc.stderr


def test_a_report_part_that_cannot_write_keeps_exit_3_across_the_process_pool(tmp_path):
    import pickle

    def part(out_dir):
        return [write_text(out_dir / "x.txt", "x")]

    with pytest.raises(report_cmd.PartFailed) as caught:
        report_cmd._run_part("tables", part, Path("/proc/silcount-test"))
    back = pickle.loads(pickle.dumps(caught.value))  # as the worker sends it to the client
    assert back.exit_code == 3 and str(back).startswith("part tables failed: UnwritableOutput: cannot write")
    with pytest.raises(report_cmd.PartFailed) as caught:
        report_cmd._run_part("tables", lambda: 1 / 0)
    assert pickle.loads(pickle.dumps(caught.value)).exit_code == 1
