//! The integration tests of non-smooth laws, contacts, events and their errors, as one
//! test binary (one build and link, every test in one harness; `Cargo.toml` lists the
//! test targets). Each file is a module: `cargo test --test nonsmooth_suite contacts::`
//! runs one.

#[path = "bearings.rs"]
mod bearings;
#[path = "contacts.rs"]
mod contacts;
#[path = "controller.rs"]
mod controller;
#[path = "errors.rs"]
mod errors;
#[path = "events.rs"]
mod events;
#[path = "identities.rs"]
mod identities;
#[path = "laws.rs"]
mod laws;
#[path = "nonsmooth.rs"]
mod nonsmooth;
#[path = "resting.rs"]
mod resting;
#[path = "s9.rs"]
mod s9;
#[path = "static_kinetic.rs"]
mod static_kinetic;
#[path = "time_stepping.rs"]
mod time_stepping;
#[path = "woodpecker.rs"]
mod woodpecker;
