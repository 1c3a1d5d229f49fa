//! Files written whole or not at all: the text goes to a temporary name beside the
//! target (`NAME.part`) and is renamed over it once complete, so a killed run never
//! leaves an `outputs.csv` or a `summary.json` that looks finished but is cut short (a
//! rename within one folder is atomic on the file systems we run on).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written under its temporary name; [`Atomic::commit`] puts it in place.
/// Dropped uncommitted, the temporary file is removed.
pub struct Atomic {
    target: PathBuf,
    part: PathBuf,
    w: Option<BufWriter<File>>,
}

impl Atomic {
    /// Starts writing `path` (as `path.part`).
    pub fn create(path: &Path) -> io::Result<Atomic> {
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(".part");
        let part = path.with_file_name(name);
        let f = File::create(&part)?;
        Ok(Atomic {
            target: path.to_path_buf(),
            part,
            w: Some(BufWriter::new(f)),
        })
    }

    /// Flushes, syncs and renames the file to its target name.
    pub fn commit(mut self) -> io::Result<()> {
        let w = self.w.take().expect("written once");
        let f = w.into_inner().map_err(|e| e.into_error())?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&self.part, &self.target)
    }
}

impl Write for Atomic {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.w.as_mut().expect("not committed").write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.w.as_mut().expect("not committed").flush()
    }
}

impl Drop for Atomic {
    fn drop(&mut self) {
        if self.w.take().is_some() {
            let _ = std::fs::remove_file(&self.part);
        }
    }
}

/// Writes `bytes` to `path` whole or not at all.
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> io::Result<()> {
    let mut a = Atomic::create(path)?;
    a.write_all(bytes.as_ref())?;
    a.commit()
}

/// Which command's results a folder holds, by a study's result file or its
/// `summary.json` (`None`: none, or unreadable as JSON).
pub fn results_in(dir: &Path) -> Option<&'static str> {
    // The studies' own result files name them.
    for (file, command) in [
        ("sensitivity.json", "sensitivity"),
        ("stress.json", "stress"),
        ("bench.json", "bench"),
    ] {
        if dir.join(file).is_file() {
            return Some(command);
        }
    }
    let text = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(
        if v.get("sweep").is_some() && v.get("cases_total").is_some() {
            "sweep"
        } else if v.get("runs").is_some() && v.get("simulator").is_some() {
            "validate"
        } else if matches!(
            v.get("kind").and_then(|k| k.as_str()),
            Some("scene" | "mechanism")
        ) {
            "run"
        } else {
            "another command"
        },
    )
}

/// Refuses to write `writes` (file names) into `dir` when it holds another command's
/// results than `command`'s (their summary would be replaced), or when one of those
/// files is one of `inputs` (the command would write over what it reads). The error
/// names the file; `Ok` when writing is safe.
pub fn claim(dir: &Path, command: &str, writes: &[&str], inputs: &[PathBuf]) -> Result<(), String> {
    if let Some(other) = results_in(dir).filter(|o| *o != command) {
        return Err(format!(
            "{}: holds the results of {other}, which this {command}'s files would replace; choose another --out",
            dir.join("summary.json").display()
        ));
    }
    for w in writes {
        let target = dir.join(w);
        if let Some(i) = inputs
            .iter()
            .find(|i| towride_mbs::input::regular::same_file(&target, i))
        {
            return Err(format!(
                "{}: is {}, an input of this {command}; it would be written over: choose another --out",
                target.display(),
                i.display()
            ));
        }
    }
    Ok(())
}
