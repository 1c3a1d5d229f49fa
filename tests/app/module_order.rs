//! The layering inside each library crate: `docs/architecture.md` lists the top-level
//! modules of `towride-mbs` and `towride-app` lowest first, and no module may use one
//! listed after it (`crate::later`, `super::later` from a top-level file, or a root
//! re-export of it). The crates' own order (solver, physics, application, binary) is
//! the compiler's: a lower crate does not depend on a higher one.
//!
//! Also: the physics crate writes no files and draws nothing.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The module order of `krate` from `docs/architecture.md`: the line
/// `` `krate`: `a` < `b` < ... `` under "## Module order".
fn documented_order(krate: &str) -> Vec<String> {
    let doc = std::fs::read_to_string(repo!("docs/architecture.md")).unwrap();
    let section = doc
        .split("## Module order")
        .nth(1)
        .expect("docs/architecture.md has a section `## Module order`");
    let prefix = format!("`{krate}`:");
    let line = section
        .lines()
        .find(|l| l.trim_start().starts_with(&prefix))
        .unwrap_or_else(|| panic!("no line `{prefix} ...` under ## Module order"));
    line.trim_start()[prefix.len()..]
        .split('<')
        .map(|m| m.trim().trim_matches('`').to_string())
        .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The code of a Rust file without comments (doc comments included: a link in a doc is
/// not a dependency) and without string literals' contents.
fn code_of(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' && (i == 0 || b[i - 1] != b'\'') {
            out.push('"');
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            out.push('"');
            i += 1;
        } else {
            out.push(b[i] as char);
            i += 1;
        }
    }
    out
}

/// The top-level modules a file's code names through `crate::` (also inside `use
/// crate::{a, b::c}`), through `super::` chains that climb to the crate root, and
/// through names the crate root re-exports (`crate::Error` is `error`'s).
fn uses(code: &str, depth: usize, reexports: &BTreeMap<String, String>) -> Vec<String> {
    let mut found = Vec::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut add = |name: String| {
        let m = reexports.get(&name).cloned().unwrap_or(name);
        if !m.is_empty() {
            found.push(m);
        }
    };
    let bytes = code.as_bytes();
    for (k, _) in code.match_indices("crate::") {
        // Not `$crate::` and not the tail of another path (`towride_mbs::crate` cannot occur).
        if k > 0
            && (bytes[k - 1] == b'$'
                || bytes[k - 1].is_ascii_alphanumeric()
                || bytes[k - 1] == b'_')
        {
            continue;
        }
        let rest = &code[k + "crate::".len()..];
        if let Some(inner) = rest.strip_prefix('{') {
            let mut level = 0;
            let mut item = true;
            for (j, c) in inner.char_indices() {
                match c {
                    '{' => level += 1,
                    '}' if level == 0 => break,
                    '}' => level -= 1,
                    ',' if level == 0 => item = true,
                    c if item && level == 0 && (c.is_alphanumeric() || c == '_') => {
                        add(ident(&inner[j..]));
                        item = false;
                    }
                    c if !c.is_whitespace() => item = false,
                    _ => {}
                }
            }
        } else {
            add(ident(rest));
        }
    }
    // `super::` repeated `depth` times reaches the crate root from a file `depth` levels
    // below it (a top-level `foo.rs` or `foo/mod.rs` is at depth 1).
    let climb = "super::".repeat(depth);
    for (k, _) in code.match_indices(&climb) {
        if k >= 7 && &code[k - 7..k] == "super::" {
            continue;
        }
        add(ident(&code[k + climb.len()..]));
    }
    found
}

fn check_crate(krate: &str) -> Vec<String> {
    let order = documented_order(krate);
    let src = Path::new(repo!("crates")).join(krate).join("src");
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    // Names the root re-exports: `pub use error::{Error, Result};` makes `crate::Error`
    // a use of `error`.
    let mut reexports = BTreeMap::new();
    for line in code_of(&lib).lines() {
        if let Some(rest) = line.trim().strip_prefix("pub use ") {
            let (module, names) = rest.split_once("::").unwrap_or((rest, ""));
            for n in names
                .trim_end_matches(';')
                .trim_matches(|c| c == '{' || c == '}')
                .split(',')
            {
                let n = n.trim();
                if !n.is_empty() && module != "crate" && order.contains(&module.to_string()) {
                    reexports.insert(n.to_string(), module.to_string());
                }
            }
        }
    }
    // Every module the crate root declares is listed, and nothing else.
    let mut declared: Vec<String> = code_of(&lib)
        .lines()
        .filter_map(|l| {
            l.trim()
                .strip_prefix("pub mod ")
                .or_else(|| l.trim().strip_prefix("mod "))
        })
        .filter_map(|l| l.strip_suffix(';').map(str::to_string))
        .collect();
    declared.sort();
    let mut listed = order.clone();
    listed.sort();
    assert_eq!(
        declared, listed,
        "{krate}: lib.rs declares these modules, docs/architecture.md lists those"
    );

    let rank = |m: &str| order.iter().position(|o| o == m);
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut upward = Vec::new();
    for f in files {
        let rel = f.strip_prefix(&src).unwrap();
        let parts: Vec<String> = rel
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        if parts == ["lib.rs"] {
            continue;
        }
        let top = parts[0].trim_end_matches(".rs").to_string();
        let depth = if parts.last().is_some_and(|p| p == "mod.rs") {
            parts.len() - 1
        } else {
            parts.len()
        };
        let Some(own) = rank(&top) else { continue };
        let code = code_of(&std::fs::read_to_string(&f).unwrap());
        for used in uses(&code, depth, &reexports) {
            if let Some(r) = rank(&used) {
                if r > own {
                    upward.push(format!(
                        "{krate}/src/{}: `{top}` uses `{used}`, listed after it",
                        rel.display()
                    ));
                }
            }
        }
    }
    upward.sort();
    upward.dedup();
    upward
}

#[test]
fn module_order() {
    let mut upward = check_crate("towride-mbs");
    upward.extend(check_crate("towride-app"));
    assert!(
        upward.is_empty(),
        "upward uses against the module order of docs/architecture.md:\n{}",
        upward.join("\n")
    );
}

/// The scanner itself: it finds uses through `crate::`, grouped `use crate::{..}`,
/// root re-exports and `super::` chains, and ignores comments and strings.
#[test]
fn the_module_order_scanner_sees_every_form_of_use() {
    let re: BTreeMap<String, String> = [("Error".to_string(), "error".to_string())].into();
    let code = code_of(
        "use crate::job::Job;\nuse crate::{report::html, sweep};\n// crate::study\nlet s = \"crate::validate\";\nfn f() -> crate::Error {}\nuse super::super::scene::X;\nmacro_rules! p { () => { $crate::input::Seg } }",
    );
    let mut found = uses(&code, 2, &re);
    found.sort();
    assert_eq!(found, ["error", "job", "report", "scene", "sweep"]);
}

/// What the physics crate must not do: write files or draw.
#[test]
fn the_physics_crate_writes_no_files_and_draws_nothing() {
    let src = Path::new(repo!("crates/towride-mbs/src"));
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let forbidden = [
        "fs::write",
        "File::create",
        "create_dir",
        "OpenOptions",
        "Writer::from_path",
        "plotters",
        "println!",
        "eprintln!",
    ];
    let mut found = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        // Unit tests write scratch files of their own.
        let code = code_of(text.split("#[cfg(test)]").next().unwrap_or(""));
        for w in forbidden {
            if code.contains(w) {
                found.push(format!("{}: {w}", f.display()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "the physics crate writes or draws:\n{}",
        found.join("\n")
    );
    let manifest = std::fs::read_to_string(repo!("crates/towride-mbs/Cargo.toml")).unwrap();
    for dep in ["towride-app", "plotters", "ab_glyph"] {
        assert!(!manifest.contains(dep), "towride-mbs depends on {dep}");
    }
}
