//! A sample of random expression scenes is compiled and run, not only expanded: the
//! derive's output for random (valid) expressions in every kind of value — masses,
//! centres of mass, origins, rpy, gravity, springs, a Bingham law — must compile, and its
//! kernels must run. (`macros/codegen/tests/fuzz.rs` expands thousands of such scenes,
//! invalid ones included; compiling each would take minutes, so a seeded sample is
//! compiled here.)

/// A small deterministic generator (64-bit LCG; Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }

    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[(self.next() % xs.len() as u64) as usize]
    }

    /// A random finite expression over `m`, `l` (and `f` when `law`) of depth ≤ `depth`.
    fn expr(&mut self, depth: u32, law: bool) -> String {
        if depth == 0 || self.next() % 3 == 0 {
            let leaves: &[&str] = if law {
                &["f", "f", "m", "l", "PI", "2.0", "0.5"]
            } else {
                &["m", "l", "PI", "2.0", "0.5", "self.m"]
            };
            return self.pick(leaves).to_string();
        }
        let a = self.expr(depth - 1, law);
        match self.next() % 6 {
            0 => format!("{a} + {}", self.expr(depth - 1, law)),
            1 => format!("{a} * {}", self.expr(depth - 1, law)),
            2 => format!("({a}) - {}", self.expr(depth - 1, law)),
            3 => format!("cos({a})"),
            4 => format!("({a}).powi(2)"),
            _ => format!("sqrt(({a}).powi(2) + 1.0)"),
        }
    }
}

fn scene(rng: &mut Lcg, k: usize) -> String {
    let mut e = |law| rng.expr(4, law);
    let (g, mass, com, origin, rpy, spring, rest, law) = (
        e(false),
        e(false),
        e(false),
        e(false),
        e(false),
        e(false),
        e(false),
        e(true),
    );
    format!(
        "mod scene_{k} {{
use filippov::Mechanism;
use filippov::nalgebra::SVector;

#[derive(Mechanism)]
#[mechanism(gravity = [0.0, -({g}), 0.0])]
#[body(a, mass = {mass} * {mass} + 1.0, com = [{com}, 0.0, 0.0], inertia = rod(m, l))]
#[joint(ja: revolute(z), parent = world, child = a, origin = [{origin}, 0.0, 0.0], rpy = [0.0, {rpy}, 0.0])]
#[body(b, mass = m, com = [l, 0.0, 0.0], inertia = rod(m, l))]
#[joint(jb: prismatic(x), parent = a, child = b)]
#[spring(jb, k = {spring} * {spring} + 1.0, rest = {rest})]
#[bingham(jb, f_crit = 0.5, law = f * ({law}) * ({law}) + f)]
struct Scene{k} {{ m: f64, l: f64 }}

pub fn run() {{
    let s = Scene{k} {{ m: 1.3, l: 0.7 }};
    let q = SVector::<f64, 2>::new(0.2, -0.1);
    let v = SVector::<f64, 2>::new(0.5, 0.3);
    let a = filippov::Mechanism::forward_dynamics(&s, &q, &v, &SVector::zeros());
    assert!(a.iter().all(|x| x.is_finite()), \"Scene{k}: {{a}}\");
}}
}}
"
    )
}

/// The sample is one program (a module per scene, `main` running each): one build and
/// one link instead of eight, and a scene that fails to compile or run is named in the
/// output.
#[test]
fn a_sample_of_random_expression_scenes_compiles_and_runs() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz_sample");
    std::fs::create_dir_all(&dir).unwrap();
    let mut rng = Lcg(0x5eed_f111_b0b0);
    let mut program = String::new();
    for k in 0..8 {
        program += &scene(&mut rng, k);
    }
    program += "\nfn main() {\n";
    for k in 0..8 {
        program += &format!("    scene_{k}::run();\n");
    }
    program += "}\n";
    let path = dir.join("sample.rs");
    std::fs::write(&path, program).unwrap();
    trybuild::TestCases::new().pass(&path);
}
