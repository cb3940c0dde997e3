//! filippov-macros: the derive entry points, kept thin; the engine is `filippov-codegen`.

use proc_macro::TokenStream;

/// Generates a specialised, fully unrolled simulator for a rigid multibody tree (closed
/// by loop joints where the mechanism has kinematic loops). See the
/// `filippov` crate documentation for the attributes.
#[proc_macro_derive(
    Mechanism,
    attributes(
        mechanism, body, joint, loop_joint, contact, spring, damper, friction, bingham, stop,
        frame, urdf_param
    )
)]
pub fn derive_mechanism(input: TokenStream) -> TokenStream {
    filippov_codegen::derive(input.into()).into()
}
