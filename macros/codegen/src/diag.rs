//! Error collection: every pass reports into one [`Diagnostics`] and keeps going, so the
//! user sees all independent mistakes of a declaration in one build.

use std::fmt::Display;

use proc_macro2::Span;
use quote::ToTokens;

#[derive(Default)]
pub struct Diagnostics {
    errors: Vec<syn::Error>,
    /// Names the user declared whose declaration already has an error (a joint whose
    /// kind or axis is wrong): a later reference to one is not a second mistake.
    excused: Vec<String>,
}

impl Diagnostics {
    pub fn new() -> Self {
        Self::default()
    }

    /// An error spanned at the tokens of `at`.
    pub fn error_at(&mut self, at: impl ToTokens, msg: impl Display) {
        self.push(syn::Error::new_spanned(at, msg));
    }

    pub fn error_span(&mut self, span: Span, msg: impl Display) {
        self.push(syn::Error::new(span, msg));
    }

    /// Adds `e` unless the same message is already reported at the same place (a
    /// mistake repeated in many attributes, each reported where it is, stays one
    /// message per place; one mistake reached by two checks is reported once).
    pub fn push(&mut self, e: syn::Error) {
        let key = |e: &syn::Error| (format!("{:?}", e.span()), e.to_string());
        let new = key(&e);
        if !self.errors.iter().any(|old| key(old) == new) {
            self.errors.push(e);
        }
    }

    /// Marks `name` as declared with an error already reported: references to it are
    /// not reported again (see [`Diagnostics::is_excused`]).
    pub fn excuse(&mut self, name: impl Display) {
        self.excused.push(name.to_string());
    }

    /// Whether `name` was declared with an error already reported.
    pub fn is_excused(&self, name: impl Display) -> bool {
        let name = name.to_string();
        self.excused.contains(&name)
    }

    pub fn has_errors(&self) -> bool {
        !self.errors.is_empty()
    }

    /// All errors combined into one, or `Ok` if there were none.
    pub fn finish(self) -> syn::Result<()> {
        let mut it = self.errors.into_iter();
        match it.next() {
            None => Ok(()),
            Some(mut first) => {
                for e in it {
                    first.combine(e);
                }
                Err(first)
            }
        }
    }
}
