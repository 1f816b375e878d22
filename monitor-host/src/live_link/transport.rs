//! The byte streams `sds link --to` reaches a checker over.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};

/// Where the checker is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Target {
    /// A serial device, set to raw mode at `baud` (by `stty`) when given.
    Serial {
        /// The device, e.g. `/dev/ttyUSB0`.
        device: PathBuf,
        /// Bits per second.
        baud: Option<u32>,
    },
    /// A TCP socket, `HOST:PORT` (QEMU's `-chardev socket`, a board's bridge).
    Tcp(String),
    /// A child process (`sh -c COMMAND`): its standard input and output.
    Exec(String),
}

/// Why `--to` is not a target, or the target cannot be reached.
#[derive(Debug, thiserror::Error)]
pub enum TargetError {
    /// The spelling.
    #[error("--to {0}: expected serial:DEVICE[@BAUD], tcp:HOST:PORT or exec:COMMAND")]
    Spelling(String),
    /// Connecting failed.
    #[error("--to {target}: {source}")]
    Connect {
        /// The target as given.
        target: String,
        /// Why.
        source: std::io::Error,
    },
}

impl std::str::FromStr for Target {
    type Err = TargetError;

    /// ```
    /// use monitor_host::live_link::Target;
    /// assert_eq!("tcp:localhost:4444".parse::<Target>().unwrap(),
    ///            Target::Tcp("localhost:4444".into()));
    /// assert!("udp:x".parse::<Target>().is_err());
    /// ```
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || TargetError::Spelling(s.to_string());
        match s.split_once(':') {
            Some(("serial", rest)) if !rest.is_empty() => {
                let (dev, baud) = match rest.rsplit_once('@') {
                    Some((d, b)) => (d, Some(b.parse().map_err(|_| bad())?)),
                    None => (rest, None),
                };
                Ok(Target::Serial {
                    device: dev.into(),
                    baud,
                })
            }
            Some(("tcp", rest)) if rest.contains(':') => Ok(Target::Tcp(rest.into())),
            Some(("exec", rest)) if !rest.trim().is_empty() => Ok(Target::Exec(rest.into())),
            _ => Err(bad()),
        }
    }
}

/// An open byte stream to the checker.
pub struct Connection {
    /// Bytes to the checker.
    pub writer: Box<dyn Write + Send>,
    /// Bytes from the checker.
    pub reader: Box<dyn Read + Send>,
    /// The child of an `exec:` target, waited for on close.
    pub child: Option<Child>,
}

impl Target {
    /// Opens the stream.
    ///
    /// # Errors
    /// [`TargetError::Connect`].
    pub fn connect(&self) -> Result<Connection, TargetError> {
        let fail = |source| TargetError::Connect {
            target: self.to_string(),
            source,
        };
        match self {
            Target::Tcp(addr) => {
                let s = TcpStream::connect(addr).map_err(fail)?;
                s.set_nodelay(true).map_err(fail)?;
                let r = s.try_clone().map_err(fail)?;
                Ok(Connection {
                    writer: Box::new(s),
                    reader: Box::new(r),
                    child: None,
                })
            }
            Target::Exec(cmd) => {
                let mut child = Command::new("sh")
                    .arg("-c")
                    .arg(cmd)
                    .stdin(Stdio::piped())
                    .stdout(Stdio::piped())
                    .spawn()
                    .map_err(fail)?;
                let (Some(w), Some(r)) = (child.stdin.take(), child.stdout.take()) else {
                    return Err(fail(std::io::Error::other("no pipes to the child")));
                };
                Ok(Connection {
                    writer: Box::new(w),
                    reader: Box::new(r),
                    child: Some(child),
                })
            }
            Target::Serial { device, baud } => {
                // Raw mode (no echo, no line editing) and the speed, without a serial crate and
                // its system libraries: the tty's own tool.
                let mut stty = Command::new("stty");
                stty.arg("-F").arg(device).args(["raw", "-echo"]);
                if let Some(b) = baud {
                    stty.arg(b.to_string());
                }
                let ok = stty.status().map_err(fail)?.success();
                if !ok {
                    return Err(fail(std::io::Error::other(
                        "stty could not set the device to raw mode",
                    )));
                }
                let f = std::fs::OpenOptions::new()
                    .read(true)
                    .write(true)
                    .open(device)
                    .map_err(fail)?;
                let r = f.try_clone().map_err(fail)?;
                Ok(Connection {
                    writer: Box::new(f),
                    reader: Box::new(r),
                    child: None,
                })
            }
        }
    }
}

impl std::fmt::Display for Target {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Target::Serial { device, baud } => {
                write!(f, "serial:{}", device.display())?;
                if let Some(b) = baud {
                    write!(f, "@{b}")?;
                }
                Ok(())
            }
            Target::Tcp(a) => write!(f, "tcp:{a}"),
            Target::Exec(c) => write!(f, "exec:{c}"),
        }
    }
}
