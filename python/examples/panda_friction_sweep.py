"""Sweep the Panda's joint friction and see where the arm comes to rest.

The Panda with Coulomb friction in every joint and stops on joints 2 and 4 (S9,
``filippov.PandaS9``) is released from one pose with the friction swept over a grid and
the initial velocities drawn at random. Each run ends at rest, stuck by its friction or
held on a stop; this script plots each joint's resting angle against the friction,
writes the table of runs (``panda_friction_sweep.npz``, one row per run with its
inputs, final state and any error) and prints a summary.

Run (after ``maturin develop --release`` in python/wheel, with matplotlib installed):

    python python/examples/panda_friction_sweep.py [output-directory]

``FILIPPOV_EXAMPLE_SAMPLES`` sets the random draws per friction value (default 20).
"""

import os
import pathlib
import sys
import time

import numpy as np

import filippov
from filippov import ensembles

# %% The scene and the sweep: 12 friction values × SAMPLES initial velocities.
samples = int(os.environ.get("FILIPPOV_EXAMPLE_SAMPLES", "20"))
out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "target/plots")
out.mkdir(parents=True, exist_ok=True)

arm = filippov.PandaS9(g=9.81, friction=1.0, e=0.3)
frictions = list(np.linspace(0.5, 6.0, 12))
q0 = [0.0, 0.8, 0.0, -1.2, 0.0, 1.0, 0.0]
v0 = [("uniform", -1.0, 1.0)] * 7
ens = arm.ensemble(3.0, parameters={"friction": frictions}, q0=q0, v0=v0, samples=samples, seed=1)

# %% Run it on every core.
start = time.perf_counter()
table = ensembles.run(ens, progress=True)
elapsed = time.perf_counter() - start
print(f"{len(table)} runs of 3 s in {elapsed:.2f} s ({len(table) / elapsed:.0f} runs/s); {table}")

# %% Keep the table: inputs, final state, switches, steps, errors.
table.save(out / "panda_friction_sweep.npz")
ok = ~table.failed
for kind in sorted(set(table["error_kind"][~ok])):
    print(f"{int((table['error_kind'] == kind).sum())} runs failed with {kind}")

# %% Which runs are at rest at the end: every joint stuck or on its stop.
rest = ok & np.all([table[f"v_{j}"] == 0.0 for j in arm.joints], axis=0)
print(f"{int(rest.sum())} of {int(ok.sum())} runs are at rest at t = 3 s")

# %% How far each joint settles from where it started, against the friction.
print("friction  mean |q_end - q0| per joint (rad)")
for f in frictions:
    rows = ok & (table["friction"] == f)
    moved = [np.abs(table[f"q_{j}"][rows] - table[f"q0_{j}"][rows]).mean() for j in arm.joints]
    print(f"{f:8.2f}  " + " ".join(f"{m:6.3f}" for m in moved))

# %% The plot: each joint's resting angle against the friction, one dot per run.
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib is not installed: no plot (pip install matplotlib)")
else:
    fig, axes = plt.subplots(1, 7, figsize=(17, 3.2), sharex=True)
    for ax, j in zip(axes, arm.joints):
        moving = ok & ~rest
        ax.plot(table["friction"][rest], table[f"q_{j}"][rest], ".", ms=3, label="at rest")
        ax.plot(table["friction"][moving], table[f"q_{j}"][moving], "x", ms=3, label="still moving")
        ax.set_title(j)
        ax.set_xlabel("joint friction [N·m]")
    axes[0].set_ylabel("angle at t = 3 s [rad]")
    axes[0].legend(fontsize=7)
    fig.suptitle("Panda (S9) released with random velocities: where each joint comes to rest")
    fig.tight_layout()
    fig.savefig(out / "panda_friction_sweep.png", dpi=110)
    print(f"plot: {out / 'panda_friction_sweep.png'}")
