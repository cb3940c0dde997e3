//! The element descriptions exist twice: as the runtime's types the generated code
//! constructs (`runtime/src/element.rs`) and as the macro engine's model of what a scene
//! declared (`macros/codegen/src/model.rs`). The emitter (`emit/nonsmooth.rs`) maps one
//! onto the other. This test fails when they drift: every variant of a runtime
//! description must be constructed by the emitter (a law the runtime knows but no
//! attribute can declare is a drift), and every variant of the engine's model must be
//! handled there (read from the sources with `syn`, as written).

use std::collections::BTreeSet;
use std::path::Path;

/// The variant names of every enum in the file at `path`, by enum name.
fn enums(path: &str) -> Vec<(String, BTreeSet<String>)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join(path)).expect("the source file");
    let file = syn::parse_file(&text).expect("it parses");
    file.items
        .into_iter()
        .filter_map(|item| match item {
            syn::Item::Enum(e) => Some((
                e.ident.to_string(),
                e.variants.iter().map(|v| v.ident.to_string()).collect(),
            )),
            _ => None,
        })
        .collect()
}

fn variants(list: &[(String, BTreeSet<String>)], name: &str) -> BTreeSet<String> {
    list.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no enum `{name}`"))
        .1
        .clone()
}

/// The emitter's source with whitespace removed (`quote!` paths as `#rt::Law::Coulomb`).
fn emitter() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(root.join("macros/codegen/src/emit/nonsmooth.rs"))
        .expect("the emitter")
        .split_whitespace()
        .collect()
}

#[test]
fn every_runtime_description_is_emitted_and_every_model_variant_handled() {
    let runtime = enums("runtime/src/element.rs");
    let model = enums("macros/codegen/src/model.rs");
    let emit = emitter();
    // Runtime → emitter: each variant is constructed as `#rt::Enum::Variant`.
    for name in ["Law", "StopKind", "ElementKind", "Selection", "Side"] {
        let vs = variants(&runtime, name);
        assert!(!vs.is_empty(), "runtime `{name}` has variants");
        for v in vs {
            assert!(
                emit.contains(&format!("#rt::{name}::{v}")),
                "runtime `{name}::{v}` is never emitted by macros/codegen/src/emit/nonsmooth.rs: \
                 a scene cannot declare it (add it to the parser, the model and the emitter)"
            );
        }
    }
    // Model → emitter: each variant of the engine's model is matched there.
    for name in ["Law", "StopKind", "ElementKind", "Selection"] {
        let vs = variants(&model, name);
        assert!(!vs.is_empty(), "model `{name}` has variants");
        for v in vs {
            assert!(
                emit.contains(&format!("{name}::{v}")),
                "the engine's `{name}::{v}` is not handled in emit/nonsmooth.rs"
            );
        }
    }
}
