//! Build script: puts `memory.x` on the linker's path and compiles the recorded route into flash.
//!
//! The routes come from the JSONL files named by `SDS_FRAMES` (separated by ':', one route per
//! file, one `monitor_core::Frame` per line, as `sds frames` writes them). Each line is decoded with `monitor_core::json::decode_frame`, the
//! decoder the host replay uses, and stored as its f32 bits in the compact table of
//! `src/table.rs`. There is no default route: without `SDS_FRAMES` the build fails.

use std::env;
use std::fs;
use std::path::PathBuf;

#[path = "src/table.rs"]
#[allow(dead_code)]
mod table;

fn main() -> Result<(), String> {
    let out = PathBuf::from(env::var_os("OUT_DIR").ok_or("OUT_DIR is not set")?);

    // memory.x for cortex-m-rt's link.x.
    fs::copy("memory.x", out.join("memory.x")).map_err(|e| format!("memory.x: {e}"))?;
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=src/table.rs");
    println!("cargo:rerun-if-env-changed=SDS_FRAMES");

    let Some(paths) = env::var_os("SDS_FRAMES") else {
        return Err("SDS_FRAMES is not set: point it at a frames JSONL file, or several separated \
                    by ':' (one route each; `sds frames ... -o FILE`, see firmware-example/README.md); \
                    the firmware has no built-in route"
            .into());
    };
    let paths: Vec<PathBuf> = env::split_paths(&paths).collect();
    let routes = u16::try_from(paths.len()).map_err(|_| "SDS_FRAMES: too many routes")?;
    let mut body = Vec::new();
    let mut total: u32 = 0;
    for path in &paths {
        println!("cargo:rerun-if-changed={}", path.display());
        let text = fs::read_to_string(path)
            .map_err(|e| format!("SDS_FRAMES: {}: cannot read: {e}", path.display()))?;
        let mut records = Vec::new();
        let mut count: u32 = 0;
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let frame = monitor_core::json::decode_frame(line.as_bytes())
                .map_err(|e| format!("SDS_FRAMES: {} line {}: {e}", path.display(), i + 1))?;
            records.extend_from_slice(&table::encode_record(&frame));
            count = count
                .checked_add(1)
                .ok_or_else(|| format!("SDS_FRAMES: {}: too many frames", path.display()))?;
        }
        if count == 0 {
            return Err(format!(
                "SDS_FRAMES: {}: no frame in the file",
                path.display()
            ));
        }
        body.extend_from_slice(&count.to_le_bytes());
        body.extend_from_slice(&records);
        total = total
            .checked_add(count)
            .ok_or("SDS_FRAMES: too many frames")?;
    }
    if routes == 0 {
        return Err("SDS_FRAMES names no file".into());
    }

    let mut bytes = table::header(routes, total).to_vec();
    bytes.extend_from_slice(&body);
    let bin = out.join("frames.bin");
    fs::write(&bin, &bytes).map_err(|e| format!("{}: {e}", bin.display()))?;
    // A static of known length and name, so `nm` can report the table's share of flash.
    let rs = format!(
        "/// The recorded routes ({routes}, {total} frames), in the format of `table`.\n\
         pub static FRAME_TABLE: [u8; {len}] = *include_bytes!({bin:?});\n",
        len = bytes.len(),
        bin = bin.display().to_string(),
    );
    fs::write(out.join("frames.rs"), rs).map_err(|e| format!("frames.rs: {e}"))?;
    Ok(())
}
