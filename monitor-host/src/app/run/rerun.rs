//! The rerun files of a scored or merged run (`--rerun-list`, `--rerun-xml`, docs/USAGE.md §9):
//! the list of routes to run again, the route XML restricted to them, and the warnings about
//! both, assembled once for every front end. The front end places the bytes where its user
//! asked and prints the warnings.

use std::path::{Path, PathBuf};

use crate::input::read::{read_input, FileKind};
use crate::input::warning::id_list;
use crate::model::report::Report;
use crate::report::rerun_list::{rerun_xml, RerunList};

/// What a run writes to run its routes again.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RerunFiles {
    /// The routes to run again (its [`RerunList::text`] is the rerun list's bytes).
    pub list: RerunList,
    /// The route XML restricted to the routes to run again, when a route XML was given.
    pub xml: Option<Vec<u8>>,
    /// The warnings to print once the files are written: ids the list refuses, then routes the
    /// route XML lacks.
    pub warnings: Vec<String>,
}

/// Why the restricted route XML cannot be made (its kind: `error_kind.rs`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RerunError {
    /// The route XML cannot be read.
    #[error("{}: cannot read: {error}", path.display())]
    Read {
        /// The route XML.
        path: PathBuf,
        /// Why.
        error: std::io::Error,
    },
    /// The route XML is not valid XML (its byte offset named).
    #[error("{}: {error}", path.display())]
    Xml {
        /// The route XML.
        path: PathBuf,
        /// Why, with the byte offset.
        error: String,
    },
}

/// The rerun files of `report` (`timeouts`: list the `timeout` routes too): the list, and with
/// `route_xml` (the route XML the routes come from) that XML restricted to every route to run
/// again, an id the list refuses included (it is the XML's own bytes there).
///
/// ```
/// use monitor_host::app::run::rerun::rerun_files;
/// use monitor_host::model::report::{assemble_rows, RunFacts};
/// let empty = assemble_rows(Vec::new(), &Default::default(), RunFacts::default());
/// let files = rerun_files(&empty, false, None)?;
/// assert!(files.list.routes.is_empty() && files.xml.is_none() && files.warnings.is_empty());
/// # Ok::<(), monitor_host::app::run::rerun::RerunError>(())
/// ```
///
/// # Errors
/// [`RerunError`]: the route XML cannot be read or is malformed.
pub fn rerun_files(
    report: &Report,
    timeouts: bool,
    route_xml: Option<&Path>,
) -> Result<RerunFiles, RerunError> {
    let list = RerunList::of(report, timeouts);
    let mut warnings: Vec<String> = list.refused_warning().into_iter().collect();
    let xml = match route_xml {
        None => None,
        Some(path) => {
            let bytes = read_input(path, FileKind::RouteXml).map_err(|error| RerunError::Read {
                path: path.to_path_buf(),
                error,
            })?;
            let ids: Vec<String> = list
                .routes
                .iter()
                .map(|(id, _)| id.clone())
                .chain(list.refused.iter().map(|(id, _)| id.clone()))
                .collect();
            let (text, absent) = rerun_xml(&bytes, &ids).map_err(|error| RerunError::Xml {
                path: path.to_path_buf(),
                error,
            })?;
            if !absent.is_empty() {
                warnings.push(format!(
                    "--rerun-xml: {} route(s) to run again are in no <route> of {}: {}",
                    absent.len(),
                    path.display(),
                    id_list(&absent)
                ));
            }
            Some(text)
        }
    };
    Ok(RerunFiles {
        list,
        xml,
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error_kind::ErrorKind;
    use crate::model::report::{assemble_rows, RunFacts};

    /// A route XML that cannot be read or is malformed names the file, as `--rerun-xml` said it.
    #[test]
    fn a_route_xml_that_cannot_be_used_names_the_file() {
        let empty = assemble_rows(Vec::new(), &Default::default(), RunFacts::default());
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("missing.xml");
        let e = rerun_files(&empty, false, Some(&missing)).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Io);
        assert!(
            e.to_string()
                .starts_with(&format!("{}: cannot read: ", missing.display())),
            "{e}"
        );
        let bad = dir.path().join("bad.xml");
        std::fs::write(&bad, "<routes><route id=\"1\"></routes>").unwrap();
        let e = rerun_files(&empty, false, Some(&bad)).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::Input);
        assert!(
            e.to_string()
                .starts_with(&format!("{}: not valid XML at byte", bad.display())),
            "{e}"
        );
        let good = dir.path().join("good.xml");
        std::fs::write(&good, "<routes><route id=\"1\"/></routes>").unwrap();
        let files = rerun_files(&empty, false, Some(&good)).unwrap();
        assert_eq!(files.xml.as_deref(), Some(&b"<routes></routes>"[..]));
        assert!(files.warnings.is_empty());
    }
}
