//! Why a sweep or a merge stopped: [`SweepError`] (a bad option or
//! field) and [`Error`].

use signorini_run::text::num;
use signorini_scene::{BuildError, SceneError};
use std::path::{Path, PathBuf};

/// What a sweep's command line gave that is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SweepError {
    /// An option out of range.
    #[error("--{option}: {message}")]
    Option {
        /// The option (`count`, `from`, `shard`, …).
        option: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The parameter path names no numeric field of the scene.
    #[error("--param {path}: {message}")]
    Param {
        /// The path given.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The scene with a swept value is invalid.
    #[error("--param {path} = {}: {error}", num(*value))]
    Value {
        /// The path.
        path: String,
        /// The value.
        value: f64,
        /// The scene's error.
        error: SceneError,
    },
    /// The scene cannot be swept (no periodic forcing to sample at).
    #[error("{0}")]
    Scene(String),
    /// Shards that do not make one sweep, or a folder to resume that is not this sweep's.
    #[error("{0}")]
    Folder(String),
}

/// Why a sweep or a merge stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The sweep's options, parameter path, values, shards or folder.
    #[error(transparent)]
    Options(#[from] SweepError),
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A scene could not be instantiated.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A file of the sweep's folder could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The output folder cannot be created.
    #[error("--out {}: {source}", path.display())]
    OutFolder {
        /// The folder.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The sweep was cancelled between runs: whole runs are kept.
    #[error("interrupted after {done} of {total} runs (whole runs kept in {dir}); continue with --resume")]
    Interrupted {
        /// Runs written.
        done: usize,
        /// Runs of the sweep (or shard).
        total: usize,
        /// The folder.
        dir: String,
    },
    /// The thread pool could not be built.
    #[error("thread pool: {0}")]
    ThreadPool(#[source] rayon::ThreadPoolBuildError),
    /// A run's rows went missing in a batch (a bug).
    #[error("a run went missing")]
    MissingRun,
}

impl Error {
    /// Whether the input was bad (options, scene, values, folder: nothing
    /// or not all was run), as opposed to a failure while running or
    /// writing. `signorini sweep` exits 2 for these.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, Error::Options(_) | Error::Scene(_) | Error::OutFolder { .. } | Error::Build(BuildError::Scene(_)))
    }
}

pub(crate) fn io(p: &Path, e: std::io::Error) -> Error {
    Error::Io { path: p.to_path_buf(), source: e }
}
