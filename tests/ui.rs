//! Compile-fail cases: each a mistake a user makes, each message spanned at the
//! offending token and saying what would be right (see `tests/ui/*.stderr`).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
