//! 64 coordinates, the documented maximum, with no `#![recursion_limit]`: each link is one
//! `#[body(name: kind, parent = …, …)]` attribute (a body and its joint), so the struct
//! carries 65 attributes, below the 128 derive helper attributes rustc expands on one item.
//! (Prismatic links along one axis keep the kernels small; the build time of large
//! chains is another matter.) Its forward dynamics runs on a 2 MiB thread in this
//! unoptimised build and falls as the closed form says.
use filippov::Mechanism;

#[derive(Mechanism)]
#[mechanism(gravity = [-9.81, 0.0, 0.0])]
#[body(b0: prismatic(x), parent = world, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b1: prismatic(x), parent = b0, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b2: prismatic(x), parent = b1, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b3: prismatic(x), parent = b2, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b4: prismatic(x), parent = b3, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b5: prismatic(x), parent = b4, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b6: prismatic(x), parent = b5, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b7: prismatic(x), parent = b6, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b8: prismatic(x), parent = b7, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b9: prismatic(x), parent = b8, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b10: prismatic(x), parent = b9, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b11: prismatic(x), parent = b10, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b12: prismatic(x), parent = b11, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b13: prismatic(x), parent = b12, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b14: prismatic(x), parent = b13, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b15: prismatic(x), parent = b14, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b16: prismatic(x), parent = b15, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b17: prismatic(x), parent = b16, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b18: prismatic(x), parent = b17, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b19: prismatic(x), parent = b18, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b20: prismatic(x), parent = b19, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b21: prismatic(x), parent = b20, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b22: prismatic(x), parent = b21, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b23: prismatic(x), parent = b22, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b24: prismatic(x), parent = b23, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b25: prismatic(x), parent = b24, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b26: prismatic(x), parent = b25, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b27: prismatic(x), parent = b26, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b28: prismatic(x), parent = b27, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b29: prismatic(x), parent = b28, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b30: prismatic(x), parent = b29, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b31: prismatic(x), parent = b30, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b32: prismatic(x), parent = b31, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b33: prismatic(x), parent = b32, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b34: prismatic(x), parent = b33, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b35: prismatic(x), parent = b34, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b36: prismatic(x), parent = b35, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b37: prismatic(x), parent = b36, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b38: prismatic(x), parent = b37, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b39: prismatic(x), parent = b38, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b40: prismatic(x), parent = b39, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b41: prismatic(x), parent = b40, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b42: prismatic(x), parent = b41, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b43: prismatic(x), parent = b42, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b44: prismatic(x), parent = b43, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b45: prismatic(x), parent = b44, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b46: prismatic(x), parent = b45, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b47: prismatic(x), parent = b46, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b48: prismatic(x), parent = b47, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b49: prismatic(x), parent = b48, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b50: prismatic(x), parent = b49, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b51: prismatic(x), parent = b50, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b52: prismatic(x), parent = b51, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b53: prismatic(x), parent = b52, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b54: prismatic(x), parent = b53, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b55: prismatic(x), parent = b54, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b56: prismatic(x), parent = b55, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b57: prismatic(x), parent = b56, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b58: prismatic(x), parent = b57, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b59: prismatic(x), parent = b58, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b60: prismatic(x), parent = b59, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b61: prismatic(x), parent = b60, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b62: prismatic(x), parent = b61, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
#[body(b63: prismatic(x), parent = b62, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
struct Chain64 { m: f64, l: f64 }

fn main() {
    use filippov::nalgebra::SVector;
    let c = Chain64 { m: 1.0, l: 0.1 };
    assert_eq!(Chain64::DOF, 64);
    let q = SVector::<f64, 64>::zeros();
    let m = c.mass_matrix(&q);
    // Every coordinate carries the links after it: M_00 is the whole chain's mass.
    assert!((m[(0, 0)] - 64.0).abs() < 1e-9 && (m[(63, 63)] - 1.0).abs() < 1e-12);
    // Forward dynamics of 64 coordinates on a 2 MiB thread, in this unoptimised build: the
    // generated code is straight-line, no recursion. Closed form: with gravity along
    // every slide the chain falls as one body, the first coordinate at −9.81, the others
    // at rest relative to it.
    let fd = std::thread::Builder::new()
        .stack_size(2 << 20)
        .spawn(move || {
            let zero = SVector::<f64, 64>::zeros();
            c.forward_dynamics(&q, &zero, &zero)
        })
        .expect("thread")
        .join()
        .expect("forward dynamics runs on a 2 MiB stack");
    assert!((fd[0] + 9.81).abs() < 1e-12, "{}", fd[0]);
    assert!(fd.iter().skip(1).all(|a| a.abs() < 1e-12), "{fd:?}");
}
