//! The `towride` command line: a thin layer over the library (one module per command):
//! argument parsing, terminal output and progress bars, nothing else.

// `println!` and `eprintln!` in this crate never panic on a closed or full stdout:
// these shadow std's (macro_rules scoping: every module below sees them), see `out.rs`.
macro_rules! println {
    () => { $crate::out::line(format_args!("")) };
    ($($t:tt)*) => { $crate::out::line(format_args!($($t)*)) };
}
macro_rules! eprintln {
    ($($t:tt)*) => { $crate::out::err_line(format_args!($($t)*)) };
}

mod analyse;
mod bench;
mod bounded;
mod calibrate;
mod comfort;
mod compare;
mod inputs;
mod interrupt;
mod modes;
mod out;
mod provenance;
mod rainflow;
mod road;
mod run;
mod scaling;
mod scene_bench;
mod scene_stress;
mod sensitivity;
mod sweep;
mod tyre_rig;
mod validate;
mod verify;

use clap::{Parser, Subcommand};

use towride_solver::Method;

#[derive(Parser, Debug)]
#[command(
    name = "towride",
    version,
    about = "Car-plus-trailer obstacle crossing with flexible bodies, checked against measurements"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the built-in published benchmark problems (IVP test set) and score them.
    Verify(verify::VerifyArgs),
    /// Integrate a mechanism file, a scene or a plan and write the outputs.
    Run(run::RunArgs),
    /// Linearise a mechanism about its equilibrium (or a run's state): modes and stiffness ratio.
    Linear(analyse::LinearArgs),
    /// Numerical health check: redundant constraints, conditioning, ratios, advice.
    Doctor(analyse::DoctorArgs),
    /// Work-precision study of a scene (`bench SCENE`) or of the solver on the test set
    /// (`bench solver`).
    Bench(BenchArgs),
    /// Mode table, mode selection and inertia invariants of a flexible body (flex/*.toml).
    Modes(modes::ModesArgs),
    /// Run a tyre test rig (cleat or quarter rig) from a TOML file.
    TyreRig(tyre_rig::TyreRigArgs),
    /// Sample a road along its two tracks: profile CSV and plot; for an ISO 8608 random
    /// road its displacement PSD against the class band.
    Road(road::RoadArgs),
    /// Source class (measured, published, scaled, assumed) of every value of property
    /// files; exit code 1 when a number has none.
    Provenance(provenance::ProvenanceArgs),
    /// Stress test of a scene: the thesis's integrator settings and worse, each case
    /// classified.
    Stress(scene_stress::StressArgs),
    /// Parameter sweep over property-file values, in parallel; `sweep merge` joins shards.
    Sweep(sweep::SweepArgs),
    /// Which inputs matter: OAT elasticities or Morris screening of a scene's outputs
    /// over its stiffness, damping and mass values.
    Sensitivity(sensitivity::SensitivityArgs),
    /// Compare the simulation with recorded runs (RUN.toml or a folder); `validate synth`
    /// writes synthetic runs.
    Validate(validate::ValidateArgs),
    /// Overlay the channels of two or more runs (HTML page and PNG) with max, min, |peak|
    /// and RMS differences against the first.
    Compare(compare::CompareArgs),
    /// Rainflow count (ASTM E1049-85) of a CSV column, its damage-equivalent load and
    /// Miner damage.
    Rainflow(rainflow::RainflowArgs),
    /// Fit property values to recorded runs (Levenberg-Marquardt), with intervals, and
    /// rate held-out runs with them.
    Calibrate(calibrate::CalibrateArgs),
    /// Ride comfort (ISO 2631-1) of acceleration columns of a CSV: weighted r.m.s.,
    /// VDV, MTVV, crest factor and the vibration total value.
    Comfort(comfort::ComfortArgs),
}

#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
struct BenchArgs {
    #[command(subcommand)]
    cmd: Option<BenchCommand>,
    #[command(flatten)]
    scene: scene_bench::BenchSceneArgs,
}

#[derive(Subcommand, Debug)]
enum BenchCommand {
    /// Wall time, steps and accuracy over a tolerance range for the built-in problems.
    Solver(bench::BenchSolverArgs),
    /// Set-up, start, integration and output times of growing models (chains, ladders of
    /// loops, the vehicle with more hitch modes) and their growth exponents.
    Scaling(scaling::ScalingArgs),
}

/// `--method` values on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub(crate) enum MethodArg {
    Variable,
    Fixed,
    /// Radau IIA of order 5 (RADAU5).
    Radau,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Variable => Method::Variable,
            MethodArg::Fixed => Method::FixedCoefficient,
            MethodArg::Radau => Method::Radau5,
        }
    }
}

fn main() {
    std::process::exit(run());
}

/// Parses the arguments, runs the command and returns the process exit code.
fn run() -> i32 {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Verify(a) => verify::run(&a),
        Command::Bench(BenchArgs {
            cmd: Some(BenchCommand::Solver(a)),
            ..
        }) => bench::run_solver(&a),
        Command::Bench(BenchArgs {
            cmd: Some(BenchCommand::Scaling(a)),
            ..
        }) => scaling::run(&a),
        Command::Bench(a) => scene_bench::run_bench(&a.scene),
        Command::Run(a) => run::run(&a),
        Command::Linear(a) => analyse::linear(&a),
        Command::Doctor(a) => analyse::doctor(&a),
        Command::Modes(a) => modes::run(&a),
        Command::TyreRig(a) => tyre_rig::run(&a),
        Command::Road(a) => road::run(&a),
        Command::Provenance(a) => provenance::run(&a),
        Command::Sweep(a) => sweep::run(&a),
        Command::Sensitivity(a) => sensitivity::run(&a),
        Command::Stress(a) => scene_stress::run_stress(&a),
        Command::Validate(a) => validate::run(&a),
        Command::Compare(a) => compare::run(&a),
        Command::Rainflow(a) => rainflow::run(&a),
        Command::Calibrate(a) => calibrate::run(&a),
        Command::Comfort(a) => comfort::run(&a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// What a command returns: the exit code, or an error printed as `error: ...` with exit
/// code 2. Library errors arrive typed and say where (file, line, field).
pub(crate) type CliResult = Result<i32, Box<dyn std::error::Error>>;

#[allow(dead_code)]
fn _assert_library_errors_convert(e: towride_app::Error) -> Box<dyn std::error::Error> {
    Box::new(e)
}

/// A progress bar on a terminal, hidden otherwise (and under `--json`).
pub(crate) fn progress(len: u64, quiet: bool) -> Bar {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return Bar(indicatif::ProgressBar::hidden());
    }
    let pb = indicatif::ProgressBar::new(len);
    pb.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg} [{elapsed}]")
            .expect("valid template"),
    );
    Bar(pb)
}

/// The library's progress reports drawn as an indicatif bar.
pub(crate) struct Bar(pub indicatif::ProgressBar);

impl towride_mbs::progress::Progress for Bar {
    fn begin(&self, total: u64) {
        self.0.set_length(total);
    }
    fn set(&self, done: u64) {
        self.0.set_position(done);
    }
    fn inc(&self, n: u64) {
        self.0.inc(n);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
    fn cancelled(&self) -> bool {
        interrupt::requested()
    }
}

impl std::ops::Deref for Bar {
    type Target = indicatif::ProgressBar;
    fn deref(&self) -> &indicatif::ProgressBar {
        &self.0
    }
}
