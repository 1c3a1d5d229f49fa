//! Reading an input file that must be a regular file of bounded size.
//!
//! Opening a named pipe blocks until a writer comes (forever, from a user's point of
//! view), and `/dev/zero` never ends: the kind of file is checked before it is opened,
//! and no more than a cap is read, so neither can hang a command or exhaust memory.
//!
//! The caps: property files (TOML, `.tir`) are hand-written, a few kB, and the largest
//! generated ones (a flexible body's mode shapes over a fine mesh) a few MB; 64 MiB is
//! ten times any of them and still parses in seconds. Logger exports are long: 1 GiB is
//! two hours of 40 channels at 5 kHz as text, more than a bump run records; files are
//! read whole into memory, so a larger one would be cut into runs anyway.

use std::io::Read;
use std::path::Path;

use super::InputError;

/// Cap on a property file (TOML, `.tir`) [bytes].
pub const PROPERTY_FILE_MAX_BYTES: u64 = 64 << 20;

/// Cap on a recording or a run's CSV (logger exports, `outputs.csv`) [bytes].
pub const DATA_FILE_MAX_BYTES: u64 = 1 << 30;

fn error(path: &Path, message: String) -> InputError {
    InputError {
        file: path.to_path_buf(),
        line: None,
        column: None,
        field: String::new(),
        message,
        kind: Default::default(),
    }
}

/// What a file that is not regular is, in words.
fn what(meta: &std::fs::Metadata) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        let t = meta.file_type();
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if meta.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// Checks that `path` is a regular file (symbolic links followed) of at most `cap`
/// bytes, without opening it; returns its size.
pub fn check_regular(path: &Path, cap: u64) -> Result<u64, InputError> {
    let meta = std::fs::metadata(path).map_err(|e| error(path, format!("cannot read: {e}")))?;
    if !meta.is_file() {
        return Err(error(
            path,
            format!(
                "is {}, not a regular file: give a file to read",
                what(&meta)
            ),
        ));
    }
    if meta.len() > cap {
        return Err(error(path, too_large(meta.len(), cap)));
    }
    Ok(meta.len())
}

fn too_large(len: u64, cap: u64) -> String {
    format!(
        "is {} MiB, more than the {} MiB read from such a file",
        len.div_ceil(1 << 20),
        cap >> 20
    )
}

/// The bytes of the regular file `path`, at most `cap` of them (an error otherwise).
pub fn read_regular(path: &Path, cap: u64) -> Result<Vec<u8>, InputError> {
    let len = check_regular(path, cap)?;
    let f = std::fs::File::open(path).map_err(|e| error(path, format!("cannot read: {e}")))?;
    let mut bytes = Vec::with_capacity(len as usize);
    // `take`: a file that grows while it is read still stops at the cap.
    f.take(cap + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| error(path, format!("cannot read: {e}")))?;
    if bytes.len() as u64 > cap {
        return Err(error(path, too_large(bytes.len() as u64, cap)));
    }
    Ok(bytes)
}

/// The text of the regular file `path` (UTF-8), at most `cap` bytes.
pub fn read_regular_text(path: &Path, cap: u64) -> Result<String, InputError> {
    String::from_utf8(read_regular(path, cap)?)
        .map_err(|e| error(path, format!("cannot read: not UTF-8 text ({e})")))
}

/// Whether `a` and `b` name one existing file (through links, `..` or another spelling):
/// a command checks its outputs against its inputs with it before writing.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        // Device and inode: a hard link is caught too, which canonical paths miss.
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
        false
    }
    #[cfg(not(unix))]
    {
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}
