//! Writes a random 3-D tree as a URDF file: oblique joint axes, rpy origins, off-axis
//! centres of mass, full inertia tensors, every seventh joint prismatic, each link's
//! parent one of the three before it. Nothing is axis-aligned, so no zero or one folds
//! in the generated code: the hard case for unrolled kernels (`robots/oblique36.urdf`
//! is this program's output for 36 joints and seed 36).
//!
//! ```text
//! cargo run --example oblique_tree -- 36 36 > robots/oblique36.urdf
//! ```
//! The arguments are the number of joints and the seed (default: 36 and the number).

/// splitmix64: a small, well-mixed generator, so that the file depends on nothing but
/// the seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The URDF text of a random oblique tree of `n` joints.
fn urdf(n: usize, seed: u64) -> String {
    let mut rng = Rng(seed);
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<!-- A random oblique 3-D tree of {n} joints, seed {seed}, written by \
         examples/oblique_tree.rs\n     (its arguments: {n} {seed}). The project's license (MIT OR \
         Apache-2.0). -->\n<robot name=\"oblique{n}\">\n  <link name=\"base\"/>\n"
    );
    let mut joints = String::new();
    for i in 0..n {
        let parent = if i == 0 {
            "base".to_string()
        } else {
            let back = (rng.uniform(0.0, 3.0) as usize).min(i - 1);
            format!("link{}", i - 1 - back)
        };
        let mut axis = [
            rng.uniform(-1.0, 1.0),
            rng.uniform(-1.0, 1.0),
            rng.uniform(0.2, 1.0),
        ];
        let norm = axis.iter().map(|x| x * x).sum::<f64>().sqrt();
        axis.iter_mut().for_each(|x| *x /= norm);
        let prismatic = i % 7 == 6;
        let o = [
            rng.uniform(0.05, 0.3),
            rng.uniform(-0.1, 0.1),
            rng.uniform(-0.1, 0.1),
        ];
        let rpy = [
            rng.uniform(-0.5, 0.5),
            rng.uniform(-0.5, 0.5),
            rng.uniform(-0.5, 0.5),
        ];
        let c = [
            rng.uniform(0.02, 0.15),
            rng.uniform(-0.05, 0.05),
            rng.uniform(-0.05, 0.05),
        ];
        let mass = rng.uniform(0.5, 2.0);
        // Moments within [0.02, 0.03] (any two sum beyond the third, as a real body's
        // must) and small products: positive definite.
        let (ixx, iyy, izz) = (
            rng.uniform(0.02, 0.03),
            rng.uniform(0.02, 0.03),
            rng.uniform(0.02, 0.03),
        );
        let (ixy, ixz, iyz) = (
            rng.uniform(-0.002, 0.002),
            rng.uniform(-0.002, 0.002),
            rng.uniform(-0.002, 0.002),
        );
        out += &format!(
            "  <link name=\"link{i}\">\n    <inertial>\n      <origin xyz=\"{:.4} {:.4} {:.4}\" rpy=\"0 0 0\"/>\n      \
             <mass value=\"{mass:.4}\"/>\n      <inertia ixx=\"{ixx:.5}\" ixy=\"{ixy:.5}\" ixz=\"{ixz:.5}\" \
             iyy=\"{iyy:.5}\" iyz=\"{iyz:.5}\" izz=\"{izz:.5}\"/>\n    </inertial>\n  </link>\n",
            c[0], c[1], c[2]
        );
        let (kind, limit) = if prismatic {
            ("prismatic", "lower=\"-0.5\" upper=\"0.5\"")
        } else {
            ("revolute", "lower=\"-3.0\" upper=\"3.0\"")
        };
        joints += &format!(
            "  <joint name=\"joint{i}\" type=\"{kind}\">\n    <parent link=\"{parent}\"/>\n    <child link=\"link{i}\"/>\n    \
             <origin xyz=\"{:.4} {:.4} {:.4}\" rpy=\"{:.4} {:.4} {:.4}\"/>\n    <axis xyz=\"{:.6} {:.6} {:.6}\"/>\n    \
             <limit {limit} effort=\"100\" velocity=\"5\"/>\n  </joint>\n",
            o[0], o[1], o[2], rpy[0], rpy[1], rpy[2], axis[0], axis[1], axis[2]
        );
    }
    out += &joints;
    out += "</robot>\n";
    out
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(36);
    let seed: u64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(n as u64);
    print!("{}", urdf(n, seed));
}
