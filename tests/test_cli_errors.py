"""The command line's errors agree with the user guide's exit-status table (issue 19): every
example value the table names gives its documented status and output, and every error of
status 1 is one line."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import shadelab_rs as sl
from shadelab_rs import cli

CUBE = str(sl.data_path("cube/cube.obj"))
GUIDE = Path(__file__).resolve().parents[1] / "docs" / "USER_GUIDE.md"


def status_table() -> dict[int, str]:
    """The rows of the guide's "Exit status" table: status -> the row's text."""
    text = GUIDE.read_text(encoding="utf-8")
    table = text.split("Exit status, for every command:", 1)[1].split("\n\n", 2)[1]
    rows = {}
    for line in table.splitlines()[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[int(cells[0])] = line
    return rows


def examples(row: str) -> list[list[str]]:
    """The command-line examples a row names in backticks (``--size 0x10``)."""
    return [m.split() for m in re.findall(r"`(--[a-z-]+ [^`]+)`", row)]


def test_the_guide_documents_statuses_0_1_2():
    rows = status_table()
    assert sorted(rows) == [0, 1, 2]
    assert "one line" in rows[1] and "usage" in rows[2]
    assert len(examples(rows[1])) >= 3 and len(examples(rows[2])) >= 3


@pytest.mark.parametrize("example", examples(status_table()[1]))
def test_status_1_examples_print_one_line(tmp_path, example, capsys):
    code = cli.main(["render", CUBE, "-o", str(tmp_path / "x.png"), *example])
    err = capsys.readouterr().err
    assert code == 1
    assert err.startswith("shadelab: error: ") and err.count("\n") == 1, err
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("example", examples(status_table()[2]))
def test_status_2_examples_print_the_usage_and_one_error_line(tmp_path, example, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["render", CUBE, "-o", str(tmp_path / "x.png"), *example])
    err = capsys.readouterr().err
    assert e.value.code == 2
    lines = err.rstrip("\n").split("\n")
    assert lines[0].startswith("usage: shadelab render")
    assert lines[-1].startswith("shadelab render: error: ")
    assert not any("error" in line for line in lines[:-1])


@pytest.mark.parametrize(
    "argv",
    [
        ["render", "missing.obj"],
        ["render", "scene.toml"],  # a missing scene file
        ["render", CUBE, "--eye", "0,0,0", "--target", "0,0,0"],
        ["render", "bad.toml"],  # a scene file with a multi-line-prone error
    ],
)
def test_every_status_1_error_is_one_line(tmp_path, argv, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.toml").write_text("version = 1\n[render]\nshading = 'toon'\n")
    assert cli.main([*argv, "-o", str(tmp_path / "x.png")]) == 1
    err = capsys.readouterr().err
    assert err.startswith("shadelab: error: ") and err.count("\n") == 1, err


def test_unknown_command_and_option_exit_2_through_a_subprocess():
    for argv in (["teleport"], ["render", CUBE, "--sharpness", "3"], ["figures", "--size", "9"]):
        r = subprocess.run(
            [sys.executable, "-m", "shadelab_rs", *argv],
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        assert r.returncode == 2, argv
        assert r.stderr.startswith("usage: shadelab") and "Traceback" not in r.stderr
        assert r.stderr.rstrip("\n").split("\n")[-1].startswith("shadelab")
