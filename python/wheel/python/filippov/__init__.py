"""filippov: compile-time specialised simulators for rigid multibody systems with
friction, dash-pots, stops and contacts.

The classes here are the robots and scenes the project ships (Panda, UR5, the
three-link arm, Solo12 and a humanoid on free bases, a box on a ramp and a
three-legged table with contacts, the canonical scenes S1–S10); a
scene of your own becomes a module of the same shape with one line of Rust
(docs/python.md).
"""

from ._filippov import *  # noqa: F401,F403
from ._filippov import (  # noqa: F401
    Ensemble,
    FilippovError,
    Integrator,
    ParameterError,
    Solution,
    SolveError,
)

#: The canonical scenes of docs/theory.md by their numbers.
CANONICAL = {
    "S1": "BinghamOscillator",
    "S2": "CubicBingham",
    "S3": "CubicBingham",
    "S4": "NonMonotoneNoJumps",
    "S5": "CoulombOscillator",
    "S6": "CoulombOscillator",
    "S7": "SupportedStop",
    "S8": "DoublePendulum",
    "S9": "PandaS9",
    "S10": "FreeBody",
}

from . import ensembles  # noqa: E402,F401
