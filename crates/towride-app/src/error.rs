//! The application's errors and [`Error`], the top-level error every one of them
//! converts into, in one `thiserror` hierarchy (as diffsol keeps its own in one
//! `error.rs`); the physics crate's errors live in its layers and are wrapped here. The
//! module sits at the bottom of the crate's module order so every layer can return its
//! error; `scene`, `validate` and `report` re-export theirs. Every error says what went
//! wrong and, for input, where: file, line and field ([`InputError`]).
//!
//! | layer | type | defined in |
//! |---|---|---|
//! | input files | [`InputError`] | `towride_mbs::input` |
//! | model building and analyses | [`ModelError`] | `towride_mbs::model` |
//! | flexible bodies | [`FlexError`] | `towride_mbs::flex` |
//! | road and tyre | [`RoadError`] | `towride_mbs::road` |
//! | the integrator | [`SolverError`] | `towride_solver` |
//! | scenes, plans, jobs, sweeps | [`SceneError`] | here |
//! | validation against measurements | [`ValidateError`], [`OnsetError`], [`PassageError`] | here |
//! | figures and reports | [`ReportError`] | here |

use std::path::PathBuf;

pub use towride_mbs::flex::FlexError;
pub use towride_mbs::input::bounds::budget::BudgetError;
pub use towride_mbs::input::InputError;
pub use towride_mbs::model::ModelError;
pub use towride_mbs::road::RoadError;
pub use towride_solver::SolverError;

/// A vehicle the design statics cannot put together, before the assembly blames it on
/// a field of the file that asked for it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// A trailer that would have to pitch too far (more than about 6 deg: the files
    /// disagree on the ball's height) or whose coupling is off the centreline.
    #[error("{origin}: the coupling at height {coupling_height_m} m (y {coupling_y_m}) cannot sit on a ball {ball_height_m} m high on the centreline without pitching the trailer by {pitch_rad:.3} rad")]
    CouplingCannotPitch {
        /// The trailer's property file.
        origin: String,
        /// Coupling height, trailer coordinates [m].
        coupling_height_m: f64,
        /// Coupling y, trailer coordinates [m].
        coupling_y_m: f64,
        /// Ball height, world [m].
        ball_height_m: f64,
        /// The pitch it would take [rad].
        pitch_rad: f64,
    },
    /// A trailer placed level whose coupling is not at the ball's height or is off the
    /// centreline.
    #[error("{origin}: the coupling at height {coupling_height_m} m (y {coupling_y_m}) must sit on the ball, {ball_height_m} m high on the centreline: a lumped trailer is placed level")]
    CouplingNotLevel {
        /// The trailer's property file or description.
        origin: String,
        /// Coupling height, trailer coordinates [m].
        coupling_height_m: f64,
        /// Coupling y, trailer coordinates [m].
        coupling_y_m: f64,
        /// Ball height, world [m].
        ball_height_m: f64,
    },
    /// An air spring that would have to pull to carry its corner.
    #[error("the air spring would carry {preload_n:.1} N at the design height: it cannot pull")]
    AirSpringPulls {
        /// The load it would carry [N].
        preload_n: f64,
    },
    /// An air spring given neither its volume nor a wheel rate.
    #[error("give volume_m3 or a wheel rate")]
    AirSpringVolume,
}

/// A signal the processing cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SignalError {
    /// A filter that cannot be designed for the sample rate.
    #[error("Butterworth low-pass needs order >= 1 and 0 < cutoff ({cutoff_hz} Hz) < rate/2 ({} Hz)", 0.5 * rate_hz)]
    FilterDesign {
        /// Filter order asked for.
        order: usize,
        /// Cutoff asked for [Hz].
        cutoff_hz: f64,
        /// Sample rate [Hz].
        rate_hz: f64,
    },
}

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
    /// A signal the processing cannot take.
    #[error(transparent)]
    Signal(#[from] SignalError),
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

/// A scene, plan or batch that cannot be loaded or run as asked.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A bad scene, plan or sweep file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A plan asked for something it does not hold.
    #[error("{}: {message}", file.display())]
    Plan {
        /// The plan file.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The solver stopped a run that had to complete (a batch case, a validation
    /// simulation); the message is the solver's.
    #[error("{name}: run failed at t = {t:.6} s: {message}")]
    RunFailed {
        /// The scene or model.
        name: String,
        /// Time reached [s].
        t: f64,
        /// The solver's message.
        message: String,
    },
    /// A run stopped on request (Ctrl-C) that had to complete.
    #[error("{name}: interrupted at t = {t:.6} s")]
    Interrupted {
        /// The scene or model.
        name: String,
        /// Time of the last sample kept [s].
        t: f64,
    },
    /// A run that would hold more samples than the memory limit allows
    /// (`input::bounds::budget`).
    #[error("{}: field `{field}`: {budget}", file.display())]
    TooLarge {
        /// The input file of the run.
        file: PathBuf,
        /// The run settings that set its size.
        field: String,
        /// Rows and memory against the limits.
        budget: BudgetError,
    },
    /// A case or group asked for by name that does not exist.
    #[error("{0}")]
    NoSuchCase(String),
    /// A shard specification that is not `I/N` with 0 <= I < N.
    #[error("{0}")]
    Shard(String),
    /// Shard summaries that cannot be merged.
    #[error("{}: {message}", file.display())]
    Merge {
        /// The shard file.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A row of a sweep summary (a shard merged, a summary resumed) or a line of its JSON
    /// twin that cannot be read, at its line and column.
    #[error("{}:{line}: field `{field}`: {message}", file.display())]
    MergeAt {
        /// The shard file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// The column's header.
        field: String,
        /// What is wrong.
        message: String,
    },
}

/// Why a recorded run could not be validated.
#[derive(Debug, thiserror::Error)]
pub enum ValidateError {
    /// A bad descriptor or measurement file.
    #[error(transparent)]
    Input(#[from] InputError),
    /// A signal the processing chain cannot take (filter design, too few samples,
    /// trigger pulses).
    #[error("{0}")]
    Signal(String),
    /// A filter the acquisition chain cannot design for the sample rate.
    #[error(transparent)]
    Filter(#[from] SignalError),
    /// Measurement and simulation do not fit together (a channel the model lacks).
    #[error("{0}")]
    Mismatch(String),
    /// The simulator failed.
    #[error("simulation: {0}")]
    Simulation(Box<Error>),
    /// A figure could not be drawn.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// A file could not be written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: std::path::PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// A file the command would write over that it did not make (a recording, or one of
    /// its inputs).
    #[error("{}: {why}; it would be written over: choose another --out", path.display())]
    WouldOverwrite {
        /// The file.
        path: std::path::PathBuf,
        /// What the file is.
        why: String,
    },
}

/// Why no onset was found in an envelope (`validate::passage`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OnsetError {
    /// The search window holds no samples.
    #[error("no samples between {lo:.3} s and {hi:.3} s")]
    EmptyWindow {
        /// Start of the window [s].
        lo: f64,
        /// End of the window [s].
        hi: f64,
    },
    /// The largest event does not stand out of the noise.
    #[error(
        "the largest event ({peak:.3} m/s^2 at {peak_s:.3} s) stands only {snr:.1} times above the noise ({noise:.3} m/s^2); {snr_min} needed"
    )]
    BelowNoise {
        /// The envelope's peak in the window [m/s^2].
        peak: f64,
        /// Its time [s].
        peak_s: f64,
        /// Peak over noise.
        snr: f64,
        /// The noise: the envelope's median [m/s^2].
        noise: f64,
        /// The ratio needed.
        snr_min: f64,
    },
    /// The event began before the window: its onset is not in it.
    #[error("the event at {peak_s:.3} s runs into the start of the search window ({lo:.3} s)")]
    RunsIntoWindow {
        /// Time of the event's peak [s].
        peak_s: f64,
        /// Start of the window [s].
        lo: f64,
    },
    /// None of the front axle's unsprung channels is recorded.
    #[error("no front-axle unsprung channel among {front:?}")]
    NoChannel {
        /// The channels looked for.
        front: Vec<String>,
    },
}

/// Why the obstacle passage was not found in the signals (`validate::passage`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PassageError {
    /// The front axle's event is not visible.
    #[error("no obstacle passage visible in the front unsprung channels {front:?}: {onset}")]
    NotVisible {
        /// The front axle's channels.
        front: Vec<String>,
        /// Why no onset was found in them.
        onset: OnsetError,
    },
}

/// A figure or report that could not be drawn or written.
#[derive(Debug, Clone, thiserror::Error)]
pub enum ReportError {
    /// The plotting backend failed (a file that cannot be written, a bad font).
    #[error("plot: {0}")]
    Plot(String),
}

impl From<String> for ReportError {
    fn from(message: String) -> Self {
        ReportError::Plot(message)
    }
}
