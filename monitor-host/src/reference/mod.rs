//! The batch reference of docs/SCORE.md §11: the same counts computed over whole arrays, sharing only the
//! f32 kernels with the core.

pub mod batch;
