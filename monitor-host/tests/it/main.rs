//! One test binary for the library's integration tests, one module per feature (ripgrep's
//! `tests/` shape). The counting allocator of `route_memory.rs` needs a binary of its own: no
//! other test may allocate while it measures.

mod figures;
mod golden;
mod live_frames;
mod maps;
mod results_files;
mod route_xml;
