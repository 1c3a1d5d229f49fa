//! `towride provenance PATH...`: the source class (measured, published, scaled, assumed)
//! of every value of the property files under the paths, and the numbers without one.

use crate::CliResult;
use std::path::PathBuf;

use clap::Args;
use towride_mbs::input::provenance::{survey, SourceClass};

#[derive(Args, Debug)]
pub struct ProvenanceArgs {
    /// Property files or folders (searched for .toml and .tir files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// List only the values of this class (measured, published, scaled, assumed).
    #[arg(long)]
    class: Option<String>,
    /// Print a JSON document instead of text.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &ProvenanceArgs) -> CliResult {
    let class = match a.class.as_deref() {
        None => None,
        Some(w) => Some(
            SourceClass::ALL
                .into_iter()
                .find(|c| c.as_str() == w)
                .ok_or_else(|| {
                    format!("--class {w}: use measured, published, scaled or assumed")
                })?,
        ),
    };
    let mut s = survey(&a.paths)?;
    if let Some(c) = class {
        for f in &mut s.files {
            f.entries.retain(|e| e.class == c);
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&s)?);
    } else {
        for f in &s.files {
            if f.entries.is_empty() && f.untagged.is_empty() {
                continue;
            }
            println!("{}", f.file);
            for e in &f.entries {
                println!("  {:>4}  {:<9}  {}: {}", e.line, e.class, e.key, e.source);
            }
            for u in &f.untagged {
                println!("  {:>4}  UNTAGGED   {}", u.line, u.key);
            }
        }
        let counts: Vec<String> = s.counts.iter().map(|(c, n)| format!("{n} {c}")).collect();
        println!(
            "{} files: {}; {} numbers without a class",
            s.files.len(),
            counts.join(", "),
            s.untagged
        );
    }
    if let Some((file, u)) = s
        .files
        .iter()
        .find_map(|f| f.untagged.first().map(|u| (&f.file, u)))
    {
        // On stderr too, where a script looks for the reason of exit code 1.
        eprintln!(
            "error: {file}:{}: field `{}`: a number without a source class{}; {} such number(s) in all{}",
            u.line,
            u.key,
            misspelt_class(file, u.line),
            s.untagged,
            if a.json { "" } else { " (listed above)" }
        );
    }
    Ok(if s.untagged > 0 { 1 } else { 0 })
}

/// `: [asumed] is not a class (did you mean 'assumed'?)` when the comment of `line`
/// starts with a bracketed word close to a class name; else "".
fn misspelt_class(file: &str, line: usize) -> String {
    let Ok(text) = towride_mbs::input::regular::read_regular_text(
        std::path::Path::new(file),
        towride_mbs::input::regular::PROPERTY_FILE_MAX_BYTES,
    ) else {
        return String::new();
    };
    let Some(l) = text.lines().nth(line.saturating_sub(1)) else {
        return String::new();
    };
    let word = l
        .split(['#', '$', '!'])
        .nth(1)
        .and_then(|c| c.trim_start().strip_prefix('['))
        .and_then(|c| c.split_once(']'))
        .map(|(w, _)| w.trim());
    let classes = SourceClass::ALL.map(|c| c.as_str());
    match word {
        Some(w) => {
            let dym = towride_mbs::input::suggest::did_you_mean(w, classes);
            if dym.is_empty() {
                String::new()
            } else {
                format!(": `[{w}]` is not a class{dym}")
            }
        }
        None => String::new(),
    }
}
