//! Where a report comes from (docs/SCORE.md §13.2): the `sds` version, the settings' hash,
//! each input file's sha256 and size, and the host name: the report's `inputs.provenance`, so
//! that parts scored on several nodes show whether they ran the same tool, settings and files.
//!
//! Telemetry files are not hashed **\[decision\]**: a run holds gigabytes of them, on the node
//! that scored it; the results files, route XML, maps and label files are.
//!
//! ```
//! use monitor_host::provenance::{settings_sha256, SDS_VERSION};
//! use monitor_host::Settings;
//! let mut s = Settings::default();
//! let h = settings_sha256(&s);
//! assert_eq!(h.len(), 64);
//! s.set("slack", "0.5")?;
//! assert_ne!(settings_sha256(&s), h);
//! s.set("provenance.host", "false")?; // not a scoring setting: not in `config`
//! assert_ne!(SDS_VERSION, "");
//! # Ok::<(), monitor_host::SettingsError>(())
//! ```

use std::io::Read;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::settings::Settings;

/// The version of `sds` that writes the report.
pub const SDS_VERSION: &str = env!("CARGO_PKG_VERSION");

/// The report's `inputs.provenance`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// The `sds` version that wrote the report.
    pub sds_version: String,
    /// sha256 of the canonical `config` JSON (compact, keys in the report's order).
    pub settings_sha256: String,
    /// The host that scored the run; null with `--set provenance.host=false`.
    pub host: Option<String>,
    /// Every input file read (results, route XML, maps, label files), in that order.
    pub files: Vec<FileDigest>,
}

/// One input file's fingerprint.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileDigest {
    /// The path as it was given or found.
    pub file: PathBuf,
    /// `results`, `routes`, `map`, `labels` or `part` (a merged report's parts).
    pub role: String,
    /// Size in bytes.
    pub size: u64,
    /// sha256 of the contents, hex; null when the file could not be read again.
    pub sha256: Option<String>,
}

impl FileDigest {
    /// The fingerprint of `file` (read in 64 KiB blocks: results files can be large, and the
    /// digest is taken after scoring, while every route's outcome is held: a 1 MiB block was
    /// 10 % of the peak heap).
    pub fn of(file: &Path, role: &str) -> FileDigest {
        let digest = || -> std::io::Result<(u64, String)> {
            // As inputs are opened: a FIFO or a device named as a file is not read.
            let mut f = crate::input::read::open_nonblocking(file)?;
            if !f.metadata()?.is_file() {
                return Err(std::io::ErrorKind::InvalidInput.into());
            }
            let mut h = Sha256::new();
            let mut buf = vec![0u8; 1 << 16];
            let mut size = 0u64;
            loop {
                let n = f.read(&mut buf)?;
                if n == 0 {
                    break;
                }
                size += n as u64;
                h.update(&buf[..n]);
            }
            Ok((size, hex(&h.finalize())))
        };
        match digest() {
            Ok((size, sha)) => FileDigest {
                file: file.to_path_buf(),
                role: role.into(),
                size,
                sha256: Some(sha),
            },
            Err(_) => FileDigest {
                file: file.to_path_buf(),
                role: role.into(),
                size: std::fs::metadata(file).map_or(0, |m| m.len()),
                sha256: None,
            },
        }
    }
}

/// sha256 of bytes, hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

fn hex(b: &[u8]) -> String {
    b.iter().map(|b| format!("{b:02x}")).collect()
}

/// sha256 of the settings' canonical `config` JSON (compact, the report's key order).
pub fn settings_sha256(settings: &Settings) -> String {
    sha256_hex(&serde_json::to_vec(settings).unwrap_or_default())
}

/// This machine's host name, if it has one: the kernel's (Linux), else `HOSTNAME` /
/// `COMPUTERNAME` (no unsafe call into libc).
pub fn host_name() -> Option<String> {
    let name = std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .or_else(|| std::env::var("COMPUTERNAME").ok())?;
    let name = name.trim();
    (!name.is_empty()).then(|| name.to_string())
}

impl Provenance {
    /// The provenance of a run scored with `settings` from `files` (path, role).
    pub fn new<'a>(
        settings: &Settings,
        files: impl IntoIterator<Item = (&'a Path, &'a str)>,
    ) -> Provenance {
        Provenance {
            sds_version: SDS_VERSION.into(),
            settings_sha256: settings_sha256(settings),
            host: settings.provenance_host.then(host_name).flatten(),
            files: files
                .into_iter()
                .map(|(f, role)| FileDigest::of(f, role))
                .collect(),
        }
    }
}
