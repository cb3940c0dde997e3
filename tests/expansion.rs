//! Snapshots of what the derive emits for every canonical scene, pretty-printed, so a
//! reader sees exactly the generated code and a change to it shows in review. The scene
//! sources are read from `src/scenes/`, the same declarations `filippov::scenes` compiles.

use std::path::Path;

fn scene_structs(file: &str) -> Vec<(String, proc_macro2::TokenStream)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src/scenes")
        .join(file);
    let src = std::fs::read_to_string(&path).expect("scene source");
    structs_of(&src)
}

fn structs_of(src: &str) -> Vec<(String, proc_macro2::TokenStream)> {
    let parsed: syn::File = syn::parse_file(src).expect("scene parses");
    parsed
        .items
        .into_iter()
        .filter_map(|item| match item {
            syn::Item::Struct(s) if s.attrs.iter().any(|a| a.path().is_ident("derive")) => {
                Some((s.ident.to_string(), quote::ToTokens::to_token_stream(&s)))
            }
            _ => None,
        })
        .collect()
}

fn pretty(tokens: proc_macro2::TokenStream) -> String {
    let file: syn::File = syn::parse2(tokens).expect("expansion is valid Rust");
    prettyplease::unparse(&file)
}

fn snapshot(file: &str) {
    for (name, tokens) in scene_structs(file) {
        let exp = filippov_codegen::expand_with_stats(tokens).expect("scene expands");
        let mut summary = String::new();
        for f in &exp.functions {
            summary.push_str(&format!(
                "// {:<26} {:>5} lets; {}\n",
                f.name, f.lets, f.ops
            ));
        }
        insta::assert_snapshot!(name.clone(), format!("{summary}\n{}", pretty(exp.tokens)));
    }
}

#[test]
fn double_pendulum() {
    snapshot("double_pendulum.rs");
}

#[test]
fn planar_arm3() {
    snapshot("arm3.rs");
}

#[test]
fn branched_tree() {
    snapshot("tree.rs");
}

#[test]
fn panda() {
    snapshot("panda.rs");
}

#[test]
fn lumped_scenes() {
    snapshot("lumped.rs");
}

#[test]
fn lie_group_scenes() {
    snapshot("lie.rs");
}

#[test]
fn closed_loops() {
    snapshot("loops.rs");
}

#[test]
fn contacts() {
    snapshot("contacts.rs");
}

#[test]
fn s9_arm() {
    snapshot("s9.rs");
}

/// What each bundled scene gets by default, without its `emit = all`: the kernels the
/// integrators call (mass matrix, forward dynamics and its Jacobian; with non-smooth
/// elements `M⁻¹` and the element laws) and nothing else.
#[test]
fn default_kernels() {
    const CORE: [&str; 5] = [
        "law",
        "mass_matrix",
        "forward_dynamics",
        "forward_dynamics_jacobian",
        "inverse_mass_matrix",
    ];
    let mut summary = String::new();
    for file in [
        "double_pendulum.rs",
        "arm3.rs",
        "tree.rs",
        "panda.rs",
        "lumped.rs",
        "lie.rs",
        "s9.rs",
    ] {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("src/scenes")
            .join(file);
        let src = std::fs::read_to_string(&path).expect("scene source");
        assert!(
            src.contains("emit = all"),
            "{file}: the bundled scenes ask for every kernel"
        );
        let src = src
            .replace("#[mechanism(emit = all)]", "")
            .replace("emit = all, ", "");
        for (name, tokens) in structs_of(&src) {
            let exp = filippov_codegen::expand_with_stats(tokens).expect("scene expands");
            summary.push_str(&format!("{name}\n"));
            // A scene with non-smooth elements always has its energies: time-stepping
            // keeps its steps passive with them.
            let nonsmooth = exp
                .functions
                .iter()
                .any(|f| f.name == "inverse_mass_matrix");
            let energy = |f: &str| nonsmooth && (f == "kinetic_energy" || f == "potential_energy");
            for f in &exp.functions {
                assert!(
                    CORE.contains(&f.name) || f.name.starts_with("__law") || energy(&f.name),
                    "{name}: `{}` emitted without being asked for",
                    f.name
                );
                summary.push_str(&format!("  {:<26} {:>5} lets; {}\n", f.name, f.lets, f.ops));
            }
            let code = exp.tokens.to_string();
            for absent in [
                "christoffel_symbols",
                "coriolis_matrix",
                if nonsmooth {
                    "delassus"
                } else {
                    "kinetic_energy"
                },
                "delassus",
            ] {
                assert!(
                    !code.contains(absent),
                    "{name}: `{absent}` in the default expansion"
                );
            }
        }
    }
    insta::assert_snapshot!("default_kernels", summary);
}
