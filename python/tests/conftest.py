"""What the Python tests share: the Rust side (examples/python_reference.rs), which
computes the same kernels and runs with the Rust API, and random scenes and states."""

import os
import pathlib
import subprocess

import numpy as np
import pytest

import filippov

ROOT = pathlib.Path(__file__).resolve().parents[2]

#: The bundled scenes on revolute and prismatic joints (frames: `KINEMATICS`).
SCENES = [
    "Panda",
    "PandaS9",
    "Ur5",
    "ThreeLinkArm",
    "DoublePendulum",
    "BinghamOscillator",
    "CubicBingham",
    "NonMonotoneNoJumps",
    "NonMonotoneMaxDissipation",
    "CoulombOscillator",
    "SupportedStop",
]
KINEMATICS = ["Panda", "PandaS9", "Ur5", "ThreeLinkArm", "DoublePendulum"]
#: The scenes with spherical or free joints (quaternions in `q`; tests/test_lie.py).
LIE = ["FreeBody", "Solo12", "Humanoid"]
NONSMOOTH = [s for s in SCENES if filippov.__dict__[s].elements]


def reference_binary():
    """The Rust program, built by the test script (or here, if missing)."""
    path = pathlib.Path(
        os.environ.get(
            "FILIPPOV_PYTHON_REFERENCE",
            ROOT / "target" / "debug" / "examples" / "python_reference",
        )
    )
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--profile", "test", "--features", "urdf", "--example", "python_reference"],
            cwd=ROOT,
            check=True,
        )
    return path


class Rust:
    """Sends requests to the Rust program and reads its answers."""

    def __init__(self, path):
        self.path = path

    def ask(self, requests):
        """One answer (a list of lines) per request, in order."""
        out = subprocess.run(
            [str(self.path)],
            input="\n".join(requests) + "\n",
            capture_output=True,
            text=True,
        )
        assert out.returncode == 0, f"the Rust side failed:\n{out.stderr}"
        out = out.stdout
        answers, lines, i = [], out.splitlines(), 0
        for r in requests:
            if r.startswith("kernel"):
                answers.append([lines[i]])
                i += 1
                continue
            start = i
            if lines[i].startswith("error"):
                i += 1
            rows = int(lines[i].split()[1])
            i += 1 + rows
            switches = int(lines[i].split()[1])
            i += 1 + switches
            answers.append(lines[start:i])
        assert i == len(lines)
        return answers


@pytest.fixture(scope="session")
def rust():
    return Rust(reference_binary())


def fmt(xs):
    """Numbers as the Rust program reads them, exactly (repr round-trips)."""
    return " ".join(repr(float(x)) for x in np.ravel(xs))


def numbers(line):
    return np.array([float(w) for w in line.split()])


def random_scene(name, rng):
    """The scene with every parameter drawn from (0.2, 0.9): positive, and inside the
    unit interval for restitutions."""
    cls = getattr(filippov, name)
    params = {p: float(rng.uniform(0.2, 0.9)) for p in cls.parameter_names}
    return cls(**params), params


def same_bits(a, b):
    """Equal bit for bit (so -0.0 ≠ 0.0 and NaN payloads count)."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    b = np.ascontiguousarray(b, dtype=np.float64)
    return a.shape == b.shape and a.view(np.uint64).tolist() == b.view(np.uint64).tolist()


def compare(sol, answer):
    """`sol` against the Rust program's answer to `run` or `control`."""
    lines = iter(answer)
    head = next(lines)
    rows = int(head.split()[1])
    assert len(sol) == rows
    expected = np.array([numbers(next(lines)) for _ in range(rows)])
    assert same_bits(sol.t, expected[:, 0])
    assert same_bits(sol.y, expected[:, 1:])
    switches = int(next(lines).split()[1])
    assert len(sol.switches) == switches
    for s in sol.switches:
        t, kind, element, before, after, jump = next(lines).split()
        assert same_bits([s["t"], s["jump"]], [float(t), float(jump)])
        assert (s["kind"], str(s["element"])) == (kind, element)
        assert (str(s["from"]), str(s["to"])) == (before, after)
