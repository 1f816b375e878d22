//! Build script: puts the board's `memory.x` (firmware-example's, the same board) on the
//! linker's path, and compiles the optional wire capture into flash for the measurement modes.
//!
//! `SDS_LINK_WIRE` names a file of the doer's bytes as it wrote them to the wire (`sds link
//! --tap DIR` writes `DIR/sent.bin`). The `bench N` and `ticks` modes feed it to the checker
//! instead of the UART; without it the capture is empty and only the `serve` mode is of use.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() -> Result<(), String> {
    let out = PathBuf::from(env::var_os("OUT_DIR").ok_or("OUT_DIR is not set")?);

    fs::copy("../memory.x", out.join("memory.x")).map_err(|e| format!("../memory.x: {e}"))?;
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=../memory.x");
    println!("cargo:rerun-if-env-changed=SDS_LINK_WIRE");

    let wire = match env::var_os("SDS_LINK_WIRE") {
        Some(path) => {
            let path = PathBuf::from(path);
            println!("cargo:rerun-if-changed={}", path.display());
            fs::read(&path).map_err(|e| format!("SDS_LINK_WIRE: {}: {e}", path.display()))?
        }
        None => Vec::new(),
    };
    fs::write(out.join("wire.bin"), &wire).map_err(|e| format!("wire.bin: {e}"))?;
    // A sized static, so that `nm -S` tells the capture's share of flash.
    fs::write(
        out.join("wire.rs"),
        format!(
            "/// The doer's bytes for `bench` and `ticks` (`SDS_LINK_WIRE`; empty without it).\n\
             static WIRE: [u8; {}] = *include_bytes!(concat!(env!(\"OUT_DIR\"), \"/wire.bin\"));\n",
            wire.len()
        ),
    )
    .map_err(|e| format!("wire.rs: {e}"))?;
    Ok(())
}
