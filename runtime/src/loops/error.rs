//! Why a closed mechanism cannot be put on (or kept on) its loops' constraints: the
//! error of the projection, the rank test and the assembly, which the integrators
//! carry as [`ErrorKind::Loops`](crate::ErrorKind::Loops).

/// Why a closed mechanism cannot be put on (or kept on) its constraint manifold.
#[derive(Clone, Debug, PartialEq)]
pub enum LoopError {
    /// The constraint Jacobian lost rank: row `row` (its name, `<loop joint>.<component>`)
    /// vanished or depends on the rows before it, `pivot` its pivot in `G M⁻¹ Gᵀ` as a
    /// fraction of the largest diagonal entry.
    Singular { row: &'static str, pivot: f64 },
    /// No configuration closes the loops near the one given: after the Newton
    /// iterations, row `row` is still off by `residual`.
    NoAssembly { row: &'static str, residual: f64 },
    /// [`assemble`](super::assemble) was given a joint name the mechanism does not have.
    UnknownJoint {
        name: String,
        joints: Vec<&'static str>,
    },
}

impl std::fmt::Display for LoopError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LoopError::Singular { row, pivot } => write!(
                f,
                "the loop constraints are singular: row `{row}` vanished or depends on the rows \
                 before it (pivot {pivot:.1e}); the mechanism is at a change point or a dead \
                 centre, or two loop joints constrain the same motion"
            ),
            LoopError::NoAssembly { row, residual } => write!(
                f,
                "no configuration closes the loops near the one given: constraint `{row}` is still \
                 off by {residual:.3e}; check the loop joints' origins and the given coordinates"
            ),
            LoopError::UnknownJoint { name, joints } => write!(
                f,
                "no joint named `{name}`; the mechanism's joints are {}",
                joints
                    .iter()
                    .map(|j| format!("`{j}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

impl std::error::Error for LoopError {}
