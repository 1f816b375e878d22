//! Host-side geometry in f64 (`SDS-SPEC.md` §1.4, §2).

pub mod map;
