//! Compile-fail cases: each a mistake a user makes, each message spanned at the
//! offending token and saying what would be right (see `tests/ui/*.stderr`); and
//! inputs at the edge of what is accepted, which must compile and run
//! (`tests/ui_pass/`).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
    t.pass("tests/ui_pass/*.rs");
}
