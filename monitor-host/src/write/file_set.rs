//! A set of files written all or nothing (docs/RELIABILITY.md, "Output"): each file through a
//! temporary file renamed over its name, each file replaced kept until the set is committed,
//! every file and folder of the set undone on an error or a signal.

use std::fs::{self, File};
use std::io::{self, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use super::error::{Context as _, WriteError};
use super::refuse::{check_target, describe, refuse_input, refuse_unsafe};
use super::scratch::{create, folder_of, scratch_name};

/// What a set has put on disk and not yet committed: the temporary files being written, the
/// files it created, the files it replaced (each with its backup) and the folders it created.
#[derive(Default)]
struct Undo {
    temps: Vec<PathBuf>,
    created: Vec<PathBuf>,
    replaced: Vec<(PathBuf, PathBuf)>,
    dirs: Vec<PathBuf>,
}

impl Undo {
    const fn new() -> Undo {
        Undo {
            temps: Vec::new(),
            created: Vec::new(),
            replaced: Vec::new(),
            dirs: Vec::new(),
        }
    }

    /// Removes what was created, puts back what was replaced (newest first), removes the
    /// folders created for it when they are empty again.
    fn roll_back(&mut self) {
        for p in self.temps.drain(..) {
            let _ = fs::remove_file(p);
        }
        for p in self.created.drain(..).rev() {
            let _ = fs::remove_file(p);
        }
        for (path, backup) in self.replaced.drain(..).rev() {
            let _ = fs::rename(backup, path);
        }
        for d in self.dirs.drain(..).rev() {
            let _ = fs::remove_dir(d);
        }
    }

    /// Keeps what was written: drops the backups of the replaced files.
    fn commit(&mut self) {
        for (_, backup) in self.replaced.drain(..) {
            let _ = fs::remove_file(backup);
        }
        self.temps.clear();
        self.created.clear();
        self.dirs.clear();
    }
}

/// Points where a front end's tests may hold a write (the command line's signal tests): never
/// set by the library.
#[derive(Clone, Copy, Debug, Default)]
pub struct Hooks {
    /// Called by [`FileSet::write_file`] once the temporary file is written, before the rename.
    pub before_rename: Option<fn()>,
    /// Called after each file [`FileSet::place`] (or its siblings) has placed.
    pub after_place: Option<fn()>,
}

/// The files written since the last [`commit`](FileSet::commit) or
/// [`roll_back`](FileSet::roll_back), in any folders: all or nothing. Its state is behind a
/// lock taken only around each creation and rename, so that another thread (a signal's) can
/// [`roll_back_then`](FileSet::roll_back_then) at any time and leave nothing behind.
///
/// ```
/// use monitor_host::write::FileSet;
/// let dir = tempfile::tempdir().unwrap();
/// let set = FileSet::new();
/// set.create_dir(&dir.path().join("tables")).unwrap();
/// set.place(&dir.path().join("tables/a.csv"), b"a\n", &[]).unwrap();
/// set.roll_back(); // the file and the folder created are gone
/// assert!(!dir.path().join("tables").exists());
/// ```
pub struct FileSet {
    state: Mutex<Undo>,
    hooks: Hooks,
}

impl Default for FileSet {
    fn default() -> Self {
        FileSet::new()
    }
}

impl FileSet {
    /// An empty set (a `const fn`: a process may keep one in a `static` for its signal thread).
    pub const fn new() -> FileSet {
        FileSet::with_hooks(Hooks {
            before_rename: None,
            after_place: None,
        })
    }

    /// An empty set calling `hooks`.
    pub const fn with_hooks(hooks: Hooks) -> FileSet {
        FileSet {
            state: Mutex::new(Undo::new()),
            hooks,
        }
    }

    fn state(&self) -> MutexGuard<'_, Undo> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Undoes every file written since the last [`commit`](Self::commit).
    pub fn roll_back(&self) {
        self.state().roll_back();
    }

    /// Keeps every file written since the last [`commit`](Self::commit) or
    /// [`roll_back`](Self::roll_back).
    pub fn commit(&self) {
        self.state().commit();
    }

    /// Rolls back, then runs `then` still holding the set's lock: a process dying of a signal
    /// does so in `then`, so that no writer starts a new file after the roll back.
    pub fn roll_back_then<R>(&self, then: impl FnOnce() -> R) -> R {
        let mut state = self.state();
        state.roll_back();
        then()
    }

    /// Creates `dir` with its missing parents, recording the folders created (removed again,
    /// when empty, by [`roll_back`](Self::roll_back)).
    ///
    /// # Errors
    /// A folder that cannot be created.
    pub fn create_dir(&self, dir: &Path) -> Result<(), WriteError> {
        let mut missing = Vec::new();
        let mut d = Some(dir);
        while let Some(p) =
            d.filter(|p| !p.as_os_str().is_empty() && fs::symlink_metadata(p).is_err())
        {
            missing.push(p.to_path_buf());
            d = p.parent();
        }
        fs::create_dir_all(dir).context_with(|| format!("cannot create {}", dir.display()))?;
        self.state().dirs.extend(missing.into_iter().rev());
        Ok(())
    }

    /// Creates `dir` ([`create_dir`](Self::create_dir)) and places each file of `files`.
    ///
    /// # Errors
    /// As [`place`](Self::place); the files placed before stay in the set.
    pub fn place_all(
        &self,
        dir: &Path,
        files: &[(PathBuf, Vec<u8>)],
        inputs: &[PathBuf],
    ) -> Result<(), WriteError> {
        self.create_dir(dir)?;
        for (path, bytes) in files {
            self.place(path, bytes, inputs)?;
        }
        Ok(())
    }

    /// Writes `bytes` at `path`, a name the tool chose (a trace, a figure, a table), through a
    /// temporary file in the same folder renamed over it: never through a symbolic link (one
    /// planted there is refused, and its target stays untouched), never over anything but a
    /// regular file that is not one of `inputs`. A file replaced is kept as a hard-linked
    /// backup until [`commit`](Self::commit), so that [`roll_back`](Self::roll_back) can put
    /// it back; a file created is removed by [`roll_back`](Self::roll_back).
    ///
    /// # Errors
    /// The refusal, or the write that failed (`cannot write PATH: ...`).
    pub fn place(&self, path: &Path, bytes: &[u8], inputs: &[PathBuf]) -> Result<(), WriteError> {
        self.place_with(path, inputs, None, &mut |f| f.write_all(bytes))
    }

    /// [`place`](Self::place) of what `write` writes into the temporary file; the new file is
    /// given `keep_mode` (the mode of the file it replaces), if any.
    ///
    /// # Errors
    /// As [`place`](Self::place); an error of `write` is the cause of `cannot write PATH`.
    pub fn place_with(
        &self,
        path: &Path,
        inputs: &[PathBuf],
        keep_mode: Option<u32>,
        write: &mut dyn FnMut(&mut File) -> io::Result<()>,
    ) -> Result<(), WriteError> {
        let existed = refuse_unsafe(path)?;
        if existed {
            let meta = fs::symlink_metadata(path)
                .context_with(|| format!("cannot inspect {}", path.display()))?;
            refuse_input(path, &meta, inputs)?;
        }
        let dir = folder_of(path);
        let tmp = scratch_name(dir, "tmp");
        let result = (|| -> Result<(), WriteError> {
            let mut f = {
                let mut state = self.state();
                state.temps.push(tmp.clone());
                create(&tmp).context_with(|| format!("cannot create {}", tmp.display()))?
            };
            if let Some(mode) = keep_mode {
                f.set_permissions(fs::Permissions::from_mode(mode))
                    .map_err(io_cause)?;
            }
            write(&mut f).map_err(io_cause)?;
            f.sync_all().map_err(io_cause)?;
            drop(f);
            let mut state = self.state();
            if existed {
                // The file replaced, kept under a second name (same folder, same file system);
                // moved aside when it cannot be linked (it is put back all the same).
                let backup = scratch_name(dir, "bak");
                fs::hard_link(path, &backup)
                    .or_else(|_| fs::rename(path, &backup))
                    .context_with(|| format!("cannot keep a copy of {}", path.display()))?;
                state.replaced.push((path.to_path_buf(), backup));
            }
            // Checked again just before the rename: a folder, device or FIFO that appeared at
            // the name since is refused (a link there is replaced by the rename, never followed).
            if let Ok(m) = fs::symlink_metadata(path) {
                if !m.is_file() && !m.file_type().is_symlink() {
                    return Err(WriteError::new(format!(
                        "{}: became {} while it was written; not replaced",
                        path.display(),
                        describe(m.file_type())
                    )));
                }
            }
            fs::rename(&tmp, path).map_err(io_cause)?;
            state.temps.retain(|t| t != &tmp);
            if !existed {
                state.created.push(path.to_path_buf());
            }
            Ok(())
        })();
        result.map_err(|e| e.context(format!("cannot write {}", path.display())))?;
        if let Some(hook) = self.hooks.after_place {
            hook();
        }
        Ok(())
    }

    /// Writes `bytes` at `path`, a file the user named besides the report (the rerun list, the
    /// rerun route XML), inside the set: refused as the report's path is (not a regular file,
    /// one of the inputs, a dangling link), a link written through to its file, the file
    /// replaced kept until [`commit`](Self::commit), as [`place`](Self::place) does.
    ///
    /// # Errors
    /// The refusal; a failed write as the cause of `no report written (fix PATH, or leave its
    /// option out)`.
    pub fn place_named(
        &self,
        path: &Path,
        bytes: &[u8],
        inputs: &[PathBuf],
    ) -> Result<(), WriteError> {
        let fix = || {
            format!(
                "no report written (fix {}, or leave its option out)",
                path.display()
            )
        };
        // A refused path names itself; a failed write says which option to fix.
        let (target, keep_mode) = check_target(path, inputs)?;
        self.place_with(&target, inputs, keep_mode, &mut |f| f.write_all(bytes))
            .map_err(|e| e.context(fix()))
    }

    /// Writes the report at `path`, the file the user named (`-o`), atomically: what `write`
    /// writes goes through a buffer into a temporary file beside it (`.<name>.sds-<pid>.tmp`),
    /// renamed over it. A path that exists and is not a regular file is refused (never
    /// replaced by a rename), and so is one of `inputs`; a link stays a link (the file it
    /// points to is replaced); a new file gets the umask's mode, a replaced one keeps its mode.
    /// The temporary file is in the set until the rename, so a signal's
    /// [`roll_back_then`](Self::roll_back_then) removes it.
    ///
    /// # Errors
    /// The refusal, or the write that failed (`cannot write PATH: ...`).
    pub fn write_file(
        &self,
        path: &Path,
        inputs: &[PathBuf],
        write: &dyn Fn(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), WriteError> {
        let (target, keep_mode) = check_target(path, inputs)?;
        let dir = folder_of(&target);
        let name = target
            .file_name()
            .ok_or_else(|| WriteError::new(format!("{}: not a file name", path.display())))?;
        let tmp = dir.join(format!(
            ".{}.sds-{}.tmp",
            name.to_string_lossy(),
            std::process::id()
        ));
        let result = self.temp_then_rename(&tmp, &target, write, keep_mode);
        if result.is_err() {
            let mut state = self.state();
            let _ = fs::remove_file(&tmp);
            state.temps.retain(|t| t != &tmp);
        }
        result.map_err(|e| e.context(format!("cannot write {}", path.display())))
    }

    /// Creation and rename happen under the set's lock, so a signal's roll back either removes
    /// a finished temporary file or ends the process before one exists: none is left behind.
    fn temp_then_rename(
        &self,
        tmp: &Path,
        target: &Path,
        write: &dyn Fn(&mut dyn Write) -> io::Result<()>,
        keep_mode: Option<u32>,
    ) -> Result<(), WriteError> {
        let mut f = {
            let mut state = self.state();
            state.temps.push(tmp.to_path_buf());
            create(tmp).context_with(|| format!("cannot create {}", tmp.display()))?
        };
        if let Some(mode) = keep_mode {
            f.set_permissions(fs::Permissions::from_mode(mode))
                .map_err(io_cause)?;
        }
        let mut buffered = io::BufWriter::new(&mut f);
        write(&mut buffered).map_err(io_cause)?;
        buffered.flush().map_err(io_cause)?;
        drop(buffered);
        f.sync_all().map_err(io_cause)?;
        drop(f);
        if let Some(hook) = self.hooks.before_rename {
            hook();
        }
        let mut state = self.state();
        // Checked again just before the rename: a device or FIFO that appeared at the path
        // since it was checked (as root, a rename would turn `/dev/null` into a regular file)
        // is refused.
        if let Ok(m) = fs::symlink_metadata(target) {
            if !m.is_file() {
                return Err(WriteError::new(format!(
                    "{}: became {} while the report was written; not replaced",
                    target.display(),
                    describe(m.file_type())
                )));
            }
        }
        fs::rename(tmp, target).map_err(io_cause)?;
        state.temps.retain(|t| t != tmp);
        Ok(())
    }
}

/// An I/O error as a [`WriteError`] saying only the I/O error (the caller adds what failed).
fn io_cause(e: io::Error) -> WriteError {
    WriteError::new(e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The set is all or nothing across folders: a roll back puts back the file replaced,
    /// removes the file created and the folders created for it, and leaves no scratch file.
    #[test]
    fn roll_back_restores_a_replaced_file_and_removes_created_folders() {
        let dir = tempfile::tempdir().unwrap();
        let old = dir.path().join("report.csv");
        fs::write(&old, b"before").unwrap();
        let set = FileSet::new();
        set.place(&old, b"after", &[]).unwrap();
        set.create_dir(&dir.path().join("t/u")).unwrap();
        set.place(&dir.path().join("t/u/a.csv"), b"a", &[]).unwrap();
        assert_eq!(fs::read(&old).unwrap(), b"after");
        set.roll_back();
        assert_eq!(fs::read(&old).unwrap(), b"before");
        let left: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["report.csv"]);
    }

    /// A commit keeps the new file and drops the backup of the one it replaced.
    #[test]
    fn commit_keeps_the_new_file_and_drops_the_backup() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.svg");
        fs::write(&path, b"old").unwrap();
        let set = FileSet::new();
        set.place(&path, b"new", &[]).unwrap();
        set.commit();
        set.roll_back(); // nothing left to undo
        assert_eq!(fs::read(&path).unwrap(), b"new");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    /// An input is never written over, at a chosen name or at the name the user gave, and a
    /// writer's error is the cause of `cannot write PATH` with no temporary file left.
    #[test]
    fn inputs_are_refused_and_a_failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("results.json");
        fs::write(&input, b"{}").unwrap();
        let set = FileSet::new();
        let inputs = [input.clone()];
        let e = set.place(&input, b"x", &inputs).unwrap_err();
        assert!(
            e.to_string().contains("this is one of the run's inputs"),
            "{e}"
        );
        let e = set
            .write_file(&input, &inputs, &|w| w.write_all(b"x"))
            .unwrap_err();
        assert!(
            e.to_string().contains("this is one of the run's inputs"),
            "{e}"
        );
        let out = dir.path().join("out.json");
        let e = set
            .write_file(&out, &[], &|_| Err(io::Error::other("disk full")))
            .unwrap_err();
        assert_eq!(
            crate::error::message(&e),
            format!("cannot write {}: disk full", out.display())
        );
        assert_eq!(fs::read(&input).unwrap(), b"{}");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
