//! Finding a town's map in a `--maps` folder (docs/SCORE.md §14.3).

use std::path::{Path, PathBuf};

/// A folder of OpenDRIVE maps.
///
/// ```
/// use monitor_host::geometry::map::MapDir;
/// let dir = MapDir::new("/nonexistent");
/// assert!(dir.find("Town01").is_none());
/// assert_eq!(dir.candidates("Town01")[3], std::path::Path::new("/nonexistent/Town01/OpenDrive/Town01.xodr"));
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MapDir {
    dir: PathBuf,
}

impl MapDir {
    /// The folder given by `--maps`.
    ///
    /// ```
    /// # use monitor_host::geometry::map::MapDir;
    /// assert_eq!(MapDir::new("maps").dir(), std::path::Path::new("maps"));
    /// ```
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        MapDir { dir: dir.into() }
    }

    /// The folder.
    ///
    /// ```
    /// # use monitor_host::geometry::map::MapDir;
    /// assert_eq!(MapDir::new("m").dir().to_str(), Some("m"));
    /// ```
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The files tried for town `town`, in order: `T.xodr`, `T_Opt.xodr`, `OpenDrive/T.xodr`,
    /// `T/OpenDrive/T.xodr` (the last two: a CARLA install's `CarlaUE4/Content/Carla/Maps`).
    ///
    /// ```
    /// # use monitor_host::geometry::map::MapDir;
    /// assert_eq!(MapDir::new("m").candidates("Town10HD")[1], std::path::Path::new("m/Town10HD_Opt.xodr"));
    /// ```
    pub fn candidates(&self, town: &str) -> [PathBuf; 4] {
        [
            self.dir.join(format!("{town}.xodr")),
            self.dir.join(format!("{town}_Opt.xodr")),
            self.dir.join("OpenDrive").join(format!("{town}.xodr")),
            self.dir
                .join(town)
                .join("OpenDrive")
                .join(format!("{town}.xodr")),
        ]
    }

    /// The map of town `town`: the first of [`MapDir::candidates`] that exists, whatever it is
    /// (a FIFO, a directory, a dangling or looping link is then refused when it is read, naming
    /// the file and the cause: never silently "no map"). A town name that is empty or holds a
    /// path separator finds nothing.
    ///
    /// ```
    /// # use monitor_host::geometry::map::MapDir;
    /// assert!(MapDir::new(".").find("../Town01").is_none());
    /// ```
    pub fn find(&self, town: &str) -> Option<PathBuf> {
        if town.is_empty() || town.contains(['/', '\\']) || town == "." || town == ".." {
            return None;
        }
        self.candidates(town)
            .into_iter()
            .find(|p| std::fs::symlink_metadata(p).is_ok())
    }
}
