//! The batch reference of spec §9: the same counts computed over whole arrays, sharing only the
//! f32 kernels with the core.

pub mod batch;
