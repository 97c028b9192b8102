//! Reports: the data model of an inspection result and its writers.

pub mod model;

pub use model::*;
