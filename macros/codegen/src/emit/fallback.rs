//! On a declaration error nothing is generated but the `compile_error!`s: no stub impl
//! is needed because the trait is only ever used through the generated impl, and a
//! missing impl then yields one clear secondary error at the use site at most.

use proc_macro2::TokenStream;

pub fn errors(e: syn::Error) -> TokenStream {
    e.to_compile_error()
}
