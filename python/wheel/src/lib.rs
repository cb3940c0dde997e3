//! The `filippov` Python wheel: the robots and scenes the project ships, as Python
//! classes, for people who do not write Rust (docs/python.md). A scene of one's own is
//! a crate of the same shape: its scenes and one `module!` line.

use filippov::scenes::{
    BinghamOscillator, CoulombOscillator, CubicBingham, DoublePendulum, FreeBody, Humanoid,
    NonMonotoneMaxDissipation, NonMonotoneNoJumps, Panda, PandaS9, RestingArm, SlidingBox, Solo12,
    SupportedStop, Table, ThreeLinkArm, Ur5,
};

filippov::python::module!(
    _filippov,
    [
        Panda {
            kinematics,
            inverse_dynamics
        },
        PandaS9 {
            nonsmooth,
            kinematics,
            inverse_dynamics
        },
        Ur5 {
            kinematics,
            inverse_dynamics
        },
        ThreeLinkArm {
            nonsmooth,
            kinematics,
            inverse_dynamics
        },
        DoublePendulum {
            kinematics,
            inverse_dynamics
        },
        RestingArm { nonsmooth },
        BinghamOscillator {
            nonsmooth,
            inverse_dynamics
        },
        CubicBingham {
            nonsmooth,
            inverse_dynamics
        },
        NonMonotoneNoJumps {
            nonsmooth,
            inverse_dynamics
        },
        NonMonotoneMaxDissipation {
            nonsmooth,
            inverse_dynamics
        },
        CoulombOscillator {
            nonsmooth,
            inverse_dynamics
        },
        SupportedStop {
            nonsmooth,
            inverse_dynamics
        },
        SlidingBox { contacts },
        Table { contacts },
        FreeBody {
            lie,
            kinematics,
            inverse_dynamics
        },
        Solo12 {
            lie,
            kinematics,
            inverse_dynamics
        },
        Humanoid {
            lie,
            kinematics,
            inverse_dynamics
        },
    ]
);
