//! The `towride` command as a user runs it: JSON fields, files written, clear errors.
//! One test binary for the CLI crate, a module per command.

/// A path to a file of the repository, as a `&'static str`.
macro_rules! repo {
    ($p:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $p)
    };
}

#[path = "../towride/validate_sim.rs"]
mod validate_sim;

mod basics;
mod modes;
mod reliability;
mod sensitivity;
mod sweep;
mod tyre_rig;
mod validate_folder;

/// Runs the binary from the repository's root with `args`.
fn towride(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_towride"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .args(args)
        .output()
        .expect("run towride")
}
