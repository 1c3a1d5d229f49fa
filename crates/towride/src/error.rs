//! Errors, one type per layer, and [`Error`], the library's top-level error that each of
//! them converts into. Every error says what went wrong and, for input, where: file,
//! line and field ([`InputError`]).
//!
//! | layer | type |
//! |---|---|
//! | input files | [`InputError`] |
//! | model building and analyses | [`ModelError`] |
//! | flexible bodies | [`FlexError`] |
//! | road and tyre | [`RoadError`] |
//! | scenes, plans, jobs, sweeps | [`SceneError`] |
//! | validation against measurements | [`ValidateError`] |
//! | figures and reports | [`ReportError`] |
//! | the integrator | [`SolverError`] (crate `towride-solver`) |

use std::path::PathBuf;

pub use crate::flex::FlexError;
pub use crate::input::InputError;
pub use crate::model::ModelError;
pub use crate::report::ReportError;
pub use crate::road::RoadError;
pub use crate::scene::SceneError;
pub use crate::validate::ValidateError;
pub use towride_solver::SolverError;

/// Any error of the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A bad input file or value.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A model that cannot be built, started or analysed.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A flexible body the reduction refuses.
    #[error(transparent)]
    Flex(#[from] FlexError),
    /// A road or tyre failure.
    #[error(transparent)]
    Road(#[from] RoadError),
    /// A scene, plan, job or sweep failure.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A validation failure.
    #[error(transparent)]
    Validate(#[from] ValidateError),
    /// A figure or report that could not be drawn.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// The integrator stopped.
    #[error(transparent)]
    Solver(#[from] SolverError),
    /// A file that could not be written or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
}

impl Error {
    /// An I/O error about `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Error {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}

/// `Result` with the library's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
