//! Standard output and error that never panic: `println!` and `eprintln!` in this crate
//! are the macros of `main.rs`, which write through here. When the reader of stdout has
//! gone (`towride modes ... | head -1`) the process ends at once with the shell's code
//! for a broken pipe, 141, and says nothing more; any other failure to write (a full
//! disk, `> /dev/full`) is one `error:` line on stderr and exit code 2. Files a command
//! writes are written whole or not at all (`towride_app::atomic`), so ending here loses
//! nothing that looked complete.

use std::io::{self, Write};

/// Writes one line to stdout.
pub fn line(args: std::fmt::Arguments) {
    let mut o = io::stdout().lock();
    if let Err(e) = o
        .write_fmt(format_args!("{args}\n"))
        .and_then(|_| o.flush())
    {
        gone(e);
    }
}

/// Writes one line to stderr; a stderr that cannot be written is ignored (there is
/// nowhere left to say so).
pub fn err_line(args: std::fmt::Arguments) {
    let _ = writeln!(io::stderr().lock(), "{args}");
}

/// Ends the process after stdout failed with `e`.
fn gone(e: io::Error) -> ! {
    if e.kind() == io::ErrorKind::BrokenPipe {
        std::process::exit(141);
    }
    err_line(format_args!("error: cannot write to standard output: {e}"));
    std::process::exit(2);
}
