"""The Python examples run as a new user would run them (with fewer runs)."""

import os
import pathlib
import subprocess
import sys

import numpy as np

import filippov

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_panda_friction_sweep(tmp_path):
    env = dict(os.environ, FILIPPOV_EXAMPLE_SAMPLES="2", MPLBACKEND="Agg")
    script = ROOT / "python" / "examples" / "panda_friction_sweep.py"
    done = subprocess.run(
        [sys.executable, str(script), str(tmp_path)], env=env, capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr
    table = filippov.ensembles.Table.load(tmp_path / "panda_friction_sweep.npz")
    assert len(table) == 24 and "q_j4" in table.names
    assert np.unique(table["friction"]).size == 12
    # The scene's stops (j2 ≤ 1.7628, j4 ≤ −0.0698, src/scenes/s9.rs) hold in every run.
    ok = ~table.failed
    assert (table["q_j2"][ok] <= 1.7628).all() and (table["q_j4"][ok] <= -0.0698).all()
    assert (tmp_path / "panda_friction_sweep.png").exists()
