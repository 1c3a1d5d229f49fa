//! Ctrl-C (SIGINT, and SIGTERM as batch schedulers send it): the first sets a flag that
//! the library polls through `Progress::cancelled`, so a run stops before its next
//! sample and a sweep starts no further case, and what was computed is written with
//! status `interrupted` (exit code 130); a second ends the process at once.
//!
//! signal-hook rather than `ctrlc` or raw `libc`: its `flag` module is exactly "set an
//! atomic flag, and exit on the second signal" with no unsafe code of ours, on libc and
//! signal-hook-registry alone (ctrlc brings nix and a thread of its own).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// Exit code of a command stopped by Ctrl-C (128 + SIGINT).
pub const EXIT: i32 = 130;

fn flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// Installs the handlers (commands that honour the flag call this: run, sweep).
pub fn install() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let f = flag();
    for sig in [SIGINT, SIGTERM] {
        // The order matters: the exit is armed only once the flag is already set.
        let armed = signal_hook::flag::register_conditional_shutdown(sig, EXIT, Arc::clone(f))
            .and_then(|_| signal_hook::flag::register(sig, Arc::clone(f)));
        if let Err(e) = armed {
            eprintln!("warning: Ctrl-C will end the command without saving: {e}");
        }
    }
}

/// True once Ctrl-C was pressed.
pub fn requested() -> bool {
    flag().load(Ordering::Relaxed)
}
