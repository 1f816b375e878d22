//! The error of a write (docs/RELIABILITY.md, "Output"): what could not be done, with its
//! cause, so that a front end prints the chain (`cannot write x: cannot create y: ...`,
//! [`crate::error::message`]).

/// A file (or folder) that could not be written, or a path refused.
#[derive(Debug, thiserror::Error)]
#[error("{what}")]
pub struct WriteError {
    what: String,
    #[source]
    source: Option<Box<dyn std::error::Error + Send + Sync + 'static>>,
}

impl WriteError {
    /// An error without a cause (a refusal).
    pub fn new(what: impl Into<String>) -> WriteError {
        WriteError {
            what: what.into(),
            source: None,
        }
    }

    /// `what` could not be done because of `source`.
    pub fn caused(
        what: impl Into<String>,
        source: impl Into<Box<dyn std::error::Error + Send + Sync + 'static>>,
    ) -> WriteError {
        WriteError {
            what: what.into(),
            source: Some(source.into()),
        }
    }

    /// This error as the cause of `what`.
    #[must_use]
    pub fn context(self, what: impl Into<String>) -> WriteError {
        WriteError::caused(what, self)
    }
}

/// `Err(e)` as the cause of `what` (anyhow's `with_context`, for this error).
pub(crate) trait Context<T> {
    /// The error, if any, as the cause of `what()`.
    fn context_with(self, what: impl FnOnce() -> String) -> Result<T, WriteError>;
}

impl<T, E> Context<T> for Result<T, E>
where
    E: Into<Box<dyn std::error::Error + Send + Sync + 'static>>,
{
    fn context_with(self, what: impl FnOnce() -> String) -> Result<T, WriteError> {
        self.map_err(|e| WriteError::caused(what(), e))
    }
}
