//! The `towride` command line: a thin layer over the library (one module per command).

mod bench;
pub mod lineplot;
pub mod plot;
mod tyre_rig;
mod verify;

use clap::{Parser, Subcommand};

use crate::solver::Method;

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
    /// Work-precision benchmarks.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Run a tyre test rig (cleat or quarter rig) from a TOML file.
    TyreRig(tyre_rig::TyreRigArgs),
}

#[derive(Subcommand, Debug)]
enum BenchCommand {
    /// Wall time, steps and accuracy over a tolerance range for the built-in problems.
    Solver(bench::BenchSolverArgs),
}

/// `--method` values on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub(crate) enum MethodArg {
    Variable,
    Fixed,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Variable => Method::Variable,
            MethodArg::Fixed => Method::FixedCoefficient,
        }
    }
}

/// Parses the arguments, runs the command and returns the process exit code.
pub fn main() -> i32 {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Verify(a) => verify::run(&a),
        Command::Bench(BenchCommand::Solver(a)) => bench::run_solver(&a),
        Command::TyreRig(a) => tyre_rig::run(&a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// A progress bar on a terminal, hidden otherwise (and under `--json`).
pub(crate) fn progress(len: u64, quiet: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let pb = indicatif::ProgressBar::new(len);
    pb.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg} [{elapsed}]")
            .expect("valid template"),
    );
    pb
}
