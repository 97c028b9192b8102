//! The simulated world: the as-machined part, the machine's true kinematics,
//! dynamics and errors, the probe's physics, noise.
//!
//! **The world knows the truth; the host never reads it.** Everything here is
//! what a real machine would *be*, not what its software would *know*. The host
//! (the measuring software) sees only commanded velocities going in and
//! readings (scales, probe deflection, status) coming out, through a seam that
//! a real machine could be plugged into later.
//!
//! Every random draw in the world goes through a caller-provided
//! `&mut impl rand::Rng` (one seeded stream: the simulated machine uses
//! `rand::rngs::Xoshiro256PlusPlus`), so
//! the same inputs and seed give identical results.

pub mod as_machined;
pub mod cmm;
pub mod collision;
pub mod contact;
pub mod dynamics;
pub mod noise;
pub mod pressed;
pub mod probe;
