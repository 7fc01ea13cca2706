"""The command-line interface."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from xpersson.cli import main

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "elastic.toml"


def test_help_imports_neither_xarray_nor_scipy():
    code = (
        "import sys\n"
        "from xpersson.cli import main\n"
        "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
        "bad = [m for m in ('xarray', 'scipy', 'pint') if m in sys.modules]\n"
        "assert not bad, bad\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    assert "run" in res.stdout and "validate" in res.stdout


def test_run_info_and_overwrite(tmp_path, capsys):
    out = tmp_path / "r.nc"
    assert main(["run", str(EXAMPLE), "-o", str(out), "--set", 'load.p0="0.1 MPa"']) == 0
    assert out.exists()
    err = capsys.readouterr().err
    assert "wrote" in err and "success" in err
    assert main(["run", str(EXAMPLE), "-o", str(out)]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "area_fraction" in text and "[1]" in text
    assert "0.127869" in text  # A/A0 of physics.md §1.4 at 0.1 MPa


def test_validate_reports_errors_to_stderr(tmp_path, capsys):
    assert main(["validate", str(EXAMPLE), "--json"]) == 0
    resolved = json.loads(capsys.readouterr().out)
    assert resolved["spectrum"]["H"] == 0.8
    assert main(["validate", str(EXAMPLE), "--set", "material.nu=0.9"]) == 2
    captured = capsys.readouterr()
    assert "material.nu" in captured.err and captured.out == ""


def test_reproduce_from_archive(tmp_path, capsys):
    out = tmp_path / "a.nc"
    assert main(["run", str(EXAMPLE), "-o", str(out)]) == 0
    assert main(["reproduce", str(out), "-o", str(tmp_path / "b.nc")]) == 0
    assert "matches" in capsys.readouterr().err


def test_console_script_installed():
    res = subprocess.run(["xpersson", "--version"], capture_output=True, text=True)
    if res.returncode != 0:
        pytest.skip("console script not on PATH")
    assert res.stdout.strip()


def test_cli_warnings_one_line_and_closed_pipe(tmp_path):
    """A warning is one line naming its class (no CLI source line); `info | head` does not
    end in a BrokenPipeError traceback."""
    out = tmp_path / "e.nc"
    # a coarse stored pressure grid: P is not resolved at small zeta, which warns
    cmd = [sys.executable, "-m", "xpersson.cli", "run", str(EXAMPLE), "-o", str(out)]
    cmd += ["--set", "output.p_points=64"]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    lines = [ln for ln in run.stderr.splitlines() if ln.strip()]
    assert any(ln.startswith("XperssonWarning: xpersson:") for ln in lines)
    assert not any("solve(" in ln for ln in lines)  # no source line of the caller
    head = subprocess.run(
        f"{sys.executable} -m xpersson.cli info {out} | head -n 1",
        shell=True,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert head.stdout.count("\n") == 1
    assert "BrokenPipeError" not in head.stderr and "Traceback" not in head.stderr
