//! Why a map could not be read: every error names the file and the element.

use std::fmt;

/// A map that cannot be used. Its message names the file, the element (road id, geometry index,
/// lane section and lane id, junction id) and what is wrong, so that the file can be fixed or left
/// out of `--maps`.
///
/// ```
/// use monitor_host::geometry::map::Map;
/// let err = Map::parse("<OpenDRIVE><road", "broken.xodr").unwrap_err();
/// assert!(err.to_string().starts_with("broken.xodr: "));
/// ```
#[derive(Debug)]
pub enum MapError {
    /// The file could not be read.
    Io {
        /// The map file.
        file: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file is not well-formed XML (for example truncated).
    Xml {
        /// The map file.
        file: String,
        /// The XML parser's message, with line and column.
        message: String,
    },
    /// The XML is well-formed but not a map this tool can use.
    Invalid {
        /// The map file.
        file: String,
        /// The element at fault, e.g. `road 12, geometry 3`.
        element: String,
        /// What is wrong with it and, where there is one, the fix.
        problem: String,
    },
}

impl MapError {
    /// The map file the error is about.
    ///
    /// ```
    /// use monitor_host::geometry::map::Map;
    /// assert_eq!(Map::parse("", "a.xodr").unwrap_err().file(), "a.xodr");
    /// ```
    pub fn file(&self) -> &str {
        match self {
            MapError::Io { file, .. }
            | MapError::Xml { file, .. }
            | MapError::Invalid { file, .. } => file,
        }
    }
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MapError::Io { file, source } => write!(f, "{file}: cannot read the map: {source}"),
            MapError::Xml { file, message } => {
                write!(f, "{file}: not a well-formed OpenDRIVE file: {message}")
            }
            MapError::Invalid {
                file,
                element,
                problem,
            } => write!(f, "{file}: {element}: {problem}"),
        }
    }
}

impl std::error::Error for MapError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MapError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}
