"""The literature's schemes (contact-stabilized, nsga, the projected
Moreau–Jean schemes) through the Python front end: `signorini.run` gives the
numbers of `signorini run` on the bar with two walls, and `signorini.sweep`
the files of `signorini sweep` on the paper's beam, byte for byte — the
same scheme by its registry name on every path."""

import csv
import subprocess

import numpy as np
import pytest

import signorini
from conftest import ROOT

SCHEMES = ["contact-stabilized", "nsga(0.5)", "moreau-jean-combined(0.5,0)"]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("scheme", SCHEMES)
def test_run_gives_the_cli_numbers(tmp_path, exe, scheme):
    text = (ROOT / "data/scenes/bar-two-walls.toml").read_text()
    text = text.replace('mass = "mod"', 'mass = "lumped"').replace('scheme = "newmark-cn"', f'scheme = "{scheme}"').replace("t_end = 8.0", "t_end = 3.0")
    assert f'scheme = "{scheme}"' in text and 'mass = "lumped"' in text
    path = tmp_path / "walls.toml"
    path.write_text(text)
    out = tmp_path / "cli"
    subprocess.run([str(exe), "run", str(path), "--out", str(out)], check=True, capture_output=True)
    r = signorini.run(path)
    rs = rows(out / "series.csv")
    assert r.status == "ok" and r.contact_dofs == [0, 100] and r.t.size == len(rs)
    for i in range(2):
        np.testing.assert_allclose(r.contact_u[:, i], [float(x[f"u_c{i}"]) for x in rs], rtol=1e-12, atol=1e-14)
    # Both walls are hit, and neither is crossed.
    assert (np.abs(r.forces[:, 0]) > 0).any() and (np.abs(r.forces[:, 1]) > 0).any()
    assert r.contact_u[:, 0].min() >= -0.02 - 1e-12 and r.contact_u[:, 1].max() <= 1e-12


def test_sweep_gives_the_cli_files(tmp_path, exe):
    scene = tmp_path / "beam.toml"
    scene.write_text('[beam]\nscene = "fig2"\nscheme = "contact-stabilized"\n\n[support]\namplitude = 0.2\nomega = 10.0\n')
    out = tmp_path / "cli"
    args = ["--param", "support.omega", "--from", "9.5", "--to", "10.5", "--count", "3", "--transient", "2", "--record", "2"]
    subprocess.run([str(exe), "sweep", str(scene), *args, "--out", str(out)], check=True, capture_output=True)
    r = signorini.sweep(scene, "support.omega", 9.5, 10.5, 3, transient=2, record=2, out=tmp_path / "py")
    for name in ("sweep.csv", "summary.csv", "impacts.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (out / name).read_bytes(), name
    assert len(r.summary["run"]) == 3 and (r.summary["impacts"] > 0).all()
