//! URDF input the derive must refuse, each with a message naming the file's element and
//! spanned at the `urdf = …` value; and the mapping of what it accepts.
#![cfg(feature = "urdf")]

use std::path::PathBuf;

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("filippov-urdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

fn expand(path: &str, extra: &str) -> Result<String, String> {
    let src = format!("#[derive(Mechanism)] #[mechanism(urdf = {path:?}{extra})] struct R;");
    let tokens: proc_macro2::TokenStream = src.parse().expect("tokens");
    filippov_codegen::expand(tokens)
        .map(|t| t.to_string())
        .map_err(|e| e.into_compile_error().to_string())
}

fn link(name: &str, mass: f64) -> String {
    format!(
        r#"<link name="{name}"><inertial><origin xyz="0 0 0.1" rpy="0 0 0"/><mass value="{mass}"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>"#
    )
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, extra: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{extra}</joint>"#
    )
}

fn robot(body: &str) -> String {
    format!(r#"<?xml version="1.0"?><robot name="r">{body}</robot>"#)
}

#[test]
fn missing_file_says_where_it_looked() {
    let e = expand("/nonexistent/robot.urdf", "").unwrap_err();
    assert!(e.contains("cannot read the URDF file"), "{e}");
    assert!(e.contains("relative to the crate's Cargo.toml"), "{e}");
}

#[test]
fn malformed_xml_is_an_error() {
    let p = write("bad.urdf", "<robot name=\"r\"><link name=\"a\"></robot>");
    let e = expand(p.to_str().unwrap(), "").unwrap_err();
    assert!(e.contains("malformed"), "{e}");
}

#[test]
fn mimic_planar_negative_mass_and_cycles_are_named() {
    let text = robot(&format!(
        "{}{}{}{}{}{}",
        link("base", 1.0),
        link("a", 1.0),
        link("b", -2.0),
        joint("ja", "revolute", "base", "a", ""),
        joint("jb", "revolute", "a", "b", r#"<mimic joint="ja"/>"#),
        "",
    ));
    let e = expand(write("mimic.urdf", &text).to_str().unwrap(), "").unwrap_err();
    assert!(
        e.contains("joint `jb` has a <mimic>") && e.contains("lock = [jb]"),
        "{e}"
    );
    assert!(e.contains("link `b` has mass -2"), "{e}");

    let text = robot(&format!(
        "{}{}{}",
        link("base", 1.0),
        link("a", 1.0),
        joint("ja", "planar", "base", "a", "")
    ));
    let e = expand(write("planar.urdf", &text).to_str().unwrap(), "").unwrap_err();
    assert!(e.contains("joint `ja` is of type Planar"), "{e}");

    let text = robot(&format!(
        "{}{}{}{}",
        link("a", 1.0),
        link("b", 1.0),
        joint("j1", "revolute", "a", "b", ""),
        joint("j2", "revolute", "b", "a", "")
    ));
    let e = expand(write("cycle.urdf", &text).to_str().unwrap(), "").unwrap_err();
    assert!(e.contains("cycle"), "{e}");
}

#[test]
fn options_map_limits_friction_damping_and_lock() {
    let text = robot(&format!(
        "{}{}{}{}{}",
        link("base", 1.0),
        link("a", 1.0),
        link("b", 1.0),
        joint(
            "ja",
            "revolute",
            "base",
            "a",
            r#"<dynamics damping="0.5" friction="0.25"/>"#
        ),
        joint("jb", "prismatic", "a", "b", ""),
    ));
    let p = write("options.urdf", &text);
    let p = p.to_str().unwrap();
    // Limits become two-sided stops, friction and damping elements, only when asked.
    let plain = expand(p, "").expect("expands");
    assert!(!plain.contains("NonSmooth"), "no elements by default");
    let full = expand(
        p,
        ", limits = stops(restitution = 0.5), joint_friction = true, joint_damping = true",
    )
    .expect("expands");
    assert!(
        full.contains("stop_ja_min") && full.contains("stop_jb_max"),
        "stops on both joints"
    );
    assert!(
        full.contains("friction_ja") || full.contains("\"ja\""),
        "friction element"
    );
    // A locked joint has no coordinate.
    let locked = expand(p, ", lock = [jb]").expect("expands");
    assert!(
        locked.contains("Mechanism < 1usize >"),
        "one coordinate left: {}",
        &locked[..200]
    );
    // Unknown names in `lock` and unknown `limits` are errors.
    let e = expand(p, ", lock = [jc]").unwrap_err();
    assert!(e.contains("`lock` names a joint `jc`"), "{e}");
    let e = expand(p, ", limits = walls").unwrap_err();
    assert!(e.contains("`limits` is `stops(restitution = e)`"), "{e}");
}
