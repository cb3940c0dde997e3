//! Expressions of any size a user can write expand to code or to a spanned error saying
//! the limit — never a stack overflow in the expander. Each expansion runs on a 4 MiB
//! thread, half of what rustc gives a proc macro. (That rustc compiles what comes
//! out of the deep cases is `macros/tests/ui_pass/deep_expressions.rs`.)

fn scene(mass: &str) -> String {
    format!(
        "#[derive(Mechanism)]
         #[body(link, mass = {mass}, com = [l, 0.0, 0.0], inertia = rod(m, l))]
         #[joint(hinge: revolute(z), parent = world, child = link)]
         struct Deep {{ m: f64, l: f64 }}"
    )
}

/// `expand` on a small stack: the error message, if any.
fn expand_small_stack(src: String) -> Result<(), String> {
    std::thread::Builder::new()
        .stack_size(4 << 20)
        .spawn(move || {
            let tokens: proc_macro2::TokenStream = src.parse().expect("valid tokens");
            filippov_codegen::expand(tokens)
                .map(|_| ())
                .map_err(|e| e.to_string())
        })
        .expect("thread")
        .join()
        .expect("no panic, no overflow")
}

#[test]
fn long_sums_and_deep_nesting_expand() {
    let terms = ["m", "l", "m * l", "sqrt(m)", "l / m"];
    let long: Vec<String> = (0..3000).map(|i| terms[i % 5].to_string()).collect();
    let sum = long.join(" + ") + " - l";
    let nested_sqrt = "sqrt(".repeat(200) + "m" + &")".repeat(200);
    let parens = "(".repeat(250) + "m" + &")".repeat(250);
    let right_nested = (0..200).fold("m".to_string(), |acc, _| format!("(m + {acc})"));
    // That rustc compiles the output is checked by `macros/tests/ui_pass/deep_expressions.rs`.
    for mass in [&sum, &nested_sqrt, &parens, &right_nested] {
        expand_small_stack(scene(mass)).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn beyond_the_limits_is_a_spanned_error() {
    let cases = [
        (
            "(".repeat(300) + "m" + &")".repeat(300),
            "nested more than 256",
        ),
        ("-".repeat(300) + "m", "minus signs in a row"),
        (
            "m".to_string() + &".sqrt()".repeat(300),
            "method calls in a chain",
        ),
        (vec!["m"; 12_000].join(" + "), "more than 20000 tokens"),
    ];
    for (mass, message) in cases {
        let err = expand_small_stack(scene(&mass)).expect_err("over a limit");
        assert!(err.contains(message), "{err}");
    }
}

/// `#[mechanism(crate = fil)]` names the crate by the user's path everywhere: no
/// `::filippov` is left in the expansion (a renamed dependency would not have one).
#[test]
fn crate_option_renames_every_path() {
    let src = "#[derive(Mechanism)]
        #[mechanism(gravity = [0.0, -9.81, 0.0], crate = fil)]
        #[body(link, mass = m, com = [l, 0.0, 0.0], inertia = rod(m, l))]
        #[joint(hinge: revolute(z), parent = world, child = link)]
        #[friction(hinge, f_crit = 0.5)]
        struct Renamed { m: f64, l: f64 }";
    let out = filippov_codegen::expand(src.parse().unwrap())
        .unwrap()
        .to_string();
    assert!(!out.contains(":: filippov"), "a ::filippov path is left");
    assert!(out.contains("fil :: runtime"));
    let quoted = "#[derive(Mechanism)]
        #[mechanism(crate = \"fil\")]
        #[body(link, mass = m)]
        #[joint(hinge: revolute(z), parent = world, child = link)]
        struct Renamed { m: f64 }";
    assert!(filippov_codegen::expand(quoted.parse().unwrap()).is_ok());
}

/// `#[body(name: kind, parent = …, origin = …, rpy = …, mass = …, …)]` is the same scene
/// as a `#[body]` and a `#[joint]` named like the body: the expansions are identical.
#[test]
fn body_with_its_joint_expands_as_the_two_attributes() {
    let split = "#[derive(Mechanism)]
        #[mechanism(gravity = [0.0, -9.81, 0.0])]
        #[body(upper, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
        #[joint(upper: revolute(z), parent = world, child = upper)]
        #[body(lower, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
        #[joint(lower: revolute(z), parent = upper, child = lower, origin = [l, 0.0, 0.0], rpy = [0.0, 0.1, 0.0])]
        #[friction(lower, f_crit = 0.5)]
        struct Arm { m: f64, l: f64 }";
    let combined = "#[derive(Mechanism)]
        #[mechanism(gravity = [0.0, -9.81, 0.0])]
        #[body(upper: revolute(z), parent = world, mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
        #[body(lower: revolute(z), parent = upper, origin = [l, 0.0, 0.0], rpy = [0.0, 0.1, 0.0], mass = m, com = [l / 2.0, 0.0, 0.0], inertia = rod(m, l))]
        #[friction(lower, f_crit = 0.5)]
        struct Arm { m: f64, l: f64 }";
    let expand = |src: &str| {
        filippov_codegen::expand(src.parse().unwrap())
            .unwrap()
            .to_string()
    };
    assert_eq!(expand(split), expand(combined));
}
