"""The examples in python/examples run and write their figure (skipped
without matplotlib)."""

import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("matplotlib")


@pytest.mark.parametrize("script,args", [("convergence_plot.py", ["--quick"]), ("beam_tip.py", [])])
def test_example_writes_its_figure(tmp_path, script, args):
    png = tmp_path / "figure.png"
    r = subprocess.run([sys.executable, str(ROOT / "python/examples" / script), str(png), *args], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
