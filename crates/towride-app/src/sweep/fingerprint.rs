//! What a sweep is, as a fingerprint kept with its results (the summary's JSON twin and
//! the journal's first line): `--resume` and `merge` refuse results whose fingerprint
//! differs from the sweep's, saying what differs, so stale or foreign cases are never
//! joined with new ones.
//!
//! The parts, each hashed with 64-bit FNV-1a (Fowler, Noll and Vo; offset basis
//! 0xcbf29ce484222325, prime 0x100000001b3) over UTF-8 text or the file's bytes, written
//! as 16 hex digits; FNV-1a is a few lines of our own, so a fingerprint stays the same on
//! every machine and every Rust version (std's `DefaultHasher` promises neither):
//! - `parameters`: each parameter's name, file, path and values, in order;
//! - `overrides`: the caller's overrides (`--set`, `--overrides`) applied to every case;
//! - `figures`: the summary layout version and the `--check` threshold (what a case
//!   reports);
//! - `inputs`: each file the cases read (named relative to the deepest folder holding
//!   them all, so a sweep resumed from another working directory matches) with the hash
//!   of its bytes.
//!
//! `hash` is the FNV-1a of the other parts' text.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::Sweep;

pub use towride_mbs::input::fnv1a;

fn hex(bytes: &[u8]) -> String {
    format!("{:016x}", fnv1a(bytes))
}

/// A sweep's fingerprint (see the module text).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fingerprint {
    /// The whole, FNV-1a of the parts below.
    pub hash: String,
    /// The parameters and their values.
    pub parameters: String,
    /// The caller's overrides.
    pub overrides: String,
    /// What each case reports (layout version, `--check` threshold).
    pub figures: String,
    /// The input files read, `[name, hash of its bytes]`.
    pub inputs: Vec<[String; 2]>,
}

impl Fingerprint {
    /// The fingerprint of `sweep` whose cases read `files`, reporting `figures`.
    pub fn of(sweep: &Sweep, files: &[PathBuf], figures: &str) -> Fingerprint {
        let mut p = String::new();
        for q in &sweep.parameters {
            p += &format!(
                "{}\n{}\n{}\n{}\n",
                q.name,
                q.file,
                q.path,
                q.values.join("\n")
            );
        }
        let o: String = sweep
            .base
            .overrides()
            .map(|o| format!("{}:{}={}\n", o.file, o.path.trim(), o.value.trim()))
            .collect();
        let canon: Vec<PathBuf> = files
            .iter()
            .map(|f| f.canonicalize().unwrap_or_else(|_| f.clone()))
            .collect();
        let root = common_dir(&canon);
        let mut inputs: Vec<[String; 2]> = canon
            .iter()
            .map(|f| {
                let name = f.strip_prefix(&root).unwrap_or(f).display().to_string();
                let bytes = std::fs::read(f).unwrap_or_default();
                [name, hex(&bytes)]
            })
            .collect();
        inputs.sort();
        inputs.dedup();
        let (parameters, overrides) = (hex(p.as_bytes()), hex(o.as_bytes()));
        let whole: String = [parameters.as_str(), &overrides, figures]
            .into_iter()
            .map(String::from)
            .chain(inputs.iter().map(|[n, h]| format!("{n} {h}")))
            .collect::<Vec<_>>()
            .join("\n");
        Fingerprint {
            hash: hex(whole.as_bytes()),
            parameters,
            overrides,
            figures: figures.into(),
            inputs,
        }
    }

    /// What differs between `self` (the results on disk) and `now` (this sweep), in
    /// words; empty when the fingerprints are equal.
    pub fn differences(&self, now: &Fingerprint) -> Vec<String> {
        let mut d = Vec::new();
        if self.parameters != now.parameters {
            d.push("the parameters or their values changed".to_string());
        }
        if self.overrides != now.overrides {
            d.push("the --set/--overrides values changed".into());
        }
        if self.figures != now.figures {
            d.push(format!(
                "what a case reports differs ({} then, {} now)",
                self.figures, now.figures
            ));
        }
        for [n, h] in &now.inputs {
            match self.inputs.iter().find(|[m, _]| m == n) {
                None => d.push(format!("{n} was not read then")),
                Some([_, g]) if g != h => d.push(format!("{n} changed")),
                _ => {}
            }
        }
        for [n, _] in &self.inputs {
            if !now.inputs.iter().any(|[m, _]| m == n) {
                d.push(format!("{n} is not read now"));
            }
        }
        if d.is_empty() && self.hash != now.hash {
            d.push("the fingerprints differ".into());
        }
        d
    }
}

/// The deepest folder holding every file of `files`.
fn common_dir(files: &[PathBuf]) -> PathBuf {
    let mut root: Option<PathBuf> = None;
    for f in files {
        let dir = f.parent().unwrap_or(Path::new("")).to_path_buf();
        root = Some(match root {
            None => dir,
            Some(r) => r
                .ancestors()
                .find(|a| dir.starts_with(a))
                .map(Path::to_path_buf)
                .unwrap_or_default(),
        });
    }
    root.unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::fnv1a;

    /// The published FNV-1a 64 test vectors (Fowler, Noll and Vo): a fingerprint written
    /// today is the one any later build computes.
    #[test]
    fn fnv1a_gives_the_published_values() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }
}
