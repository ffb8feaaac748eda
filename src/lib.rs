//! # observer-workbench
//!
//! Exact design and verification of Luenberger state observers.
//!
//! Layers point one way: [`algebra`] (number types) → [`linalg`] and [`poly`] (matrices,
//! polynomials, rational functions) → [`syntax`] (reading and printing what users type).
#![warn(missing_docs)]

mod names;

pub mod algebra;
#[cfg(feature = "cli")]
pub mod book;
pub mod canonical_form;
#[cfg(feature = "cli")]
pub mod cli;
pub mod control;
pub mod derivation;
pub mod exercise;
pub mod fuzzing;
pub mod linalg;
pub mod observability;
pub mod observer;
pub mod poly;
pub mod simulation;
pub mod syntax;
pub mod system;
pub mod worked;
