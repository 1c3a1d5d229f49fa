//! Property overrides: replace values in input files as they are read, by file and
//! TOML path, without touching the files. Parameter sweeps use it to vary any value of
//! any property file ("vehicles/car_front.toml" `spring.stiffness_n_m` = 2.5e4) through
//! the normal loaders, so every override is validated like a hand-edited file.
//!
//! Overrides are set per thread for the duration of a closure ([`with`]), so parallel
//! sweep cases do not see each other's values.

use std::cell::RefCell;
use std::path::Path;

use toml_edit::{DocumentMut, Item, Value};

use super::InputError;

/// One value to replace: in every file whose path ends with `file`, at the dotted TOML
/// path `path` (`table.key`, `array[2].key`), the TOML value `value` (`2.5e4`, `"text"`,
/// `[1, 2]`).
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    pub file: String,
    pub path: String,
    pub value: String,
}

thread_local! {
    static ACTIVE: RefCell<Vec<Override>> = const { RefCell::new(Vec::new()) };
}

/// Runs `f` with `list` active on this thread (nested calls add to the outer list).
pub fn with<R>(list: &[Override], f: impl FnOnce() -> R) -> R {
    let before = ACTIVE.with(|a| {
        let mut a = a.borrow_mut();
        let n = a.len();
        a.extend_from_slice(list);
        n
    });
    let out = f();
    ACTIVE.with(|a| a.borrow_mut().truncate(before));
    out
}

/// Applies the active overrides that match `path` to its text.
pub fn apply(path: &Path, text: String) -> Result<String, InputError> {
    let list: Vec<Override> = ACTIVE.with(|a| {
        a.borrow()
            .iter()
            .filter(|o| path.ends_with(&o.file))
            .cloned()
            .collect()
    });
    if list.is_empty() {
        return Ok(text);
    }
    let err = |field: &str, message: String| InputError {
        file: path.to_path_buf(),
        line: None,
        column: None,
        field: field.to_string(),
        message,
    };
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e| err("", format!("cannot apply overrides: {e}")))?;
    for o in &list {
        let value: Value = o.value.parse().map_err(|e| {
            err(
                &o.path,
                format!("override value `{}` is not TOML: {e}", o.value),
            )
        })?;
        match locate(doc.as_item_mut(), &o.path) {
            Some(slot) => *slot = Item::Value(value),
            // A key missing from an existing table is added (the file's own checks
            // then refuse a key that does not belong there).
            None => insert(doc.as_item_mut(), &o.path, value)
                .ok_or_else(|| err(&o.path, "override path not found in the file".into()))?,
        }
    }
    Ok(doc.to_string())
}

type Segs = [(String, Option<usize>)];

/// `table.key`, `array[2].key` as (key, index) segments.
fn segments(path: &str) -> Option<Vec<(String, Option<usize>)>> {
    path.split('.')
        .map(|part| match part.find('[') {
            Some(i) => {
                let idx: usize = part[i + 1..].strip_suffix(']')?.parse().ok()?;
                Some((part[..i].to_string(), Some(idx)))
            }
            None => Some((part.to_string(), None)),
        })
        .collect()
}

/// The item at a dotted path with `[k]` indices into arrays of tables.
fn locate<'a>(item: &'a mut Item, path: &str) -> Option<&'a mut Item> {
    walk(item, &segments(path)?)
}

/// Adds `value` under the last key of `path` in the table its parent path names.
fn insert(item: &mut Item, path: &str, value: Value) -> Option<()> {
    let (parent, key) = match path.rsplit_once('.') {
        Some((p, k)) => (Some(p), k),
        None => (None, path),
    };
    if key.contains('[') {
        return None;
    }
    let table = match parent {
        Some(p) => locate(item, p)?,
        None => item,
    };
    table.as_table_like_mut()?.insert(key, Item::Value(value));
    Some(())
}

fn walk<'a>(item: &'a mut Item, segs: &Segs) -> Option<&'a mut Item> {
    let Some(((key, idx), rest)) = segs.split_first() else {
        return Some(item);
    };
    let next = item.as_table_like_mut()?.get_mut(key)?;
    match idx {
        None => walk(next, rest),
        Some(k) => match next {
            Item::ArrayOfTables(a) => walk_table(a.get_mut(*k)?, rest),
            _ => None,
        },
    }
}

fn walk_table<'a>(t: &'a mut toml_edit::Table, segs: &Segs) -> Option<&'a mut Item> {
    let ((key, idx), rest) = segs.split_first()?;
    let next = t.get_mut(key)?;
    match idx {
        None => walk(next, rest),
        Some(k) => match next {
            Item::ArrayOfTables(a) => walk_table(a.get_mut(*k)?, rest),
            _ => None,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_replace_values_by_path_and_refuse_missing_paths() {
        let text =
            "[spring]\nstiffness_n_m = 1.0\n\n[[axle]]\nmass_kg = 2.0\n[[axle]]\nmass_kg = 3.0\n"
                .to_string();
        let p = Path::new("vehicles/car.toml");
        let ov = |path: &str, value: &str| Override {
            file: "car.toml".into(),
            path: path.into(),
            value: value.into(),
        };
        let out = with(
            &[
                ov("spring.stiffness_n_m", "2.5e4"),
                ov("axle[1].mass_kg", "7.5"),
            ],
            || apply(p, text.clone()),
        )
        .unwrap();
        let doc: DocumentMut = out.parse().unwrap();
        assert_eq!(doc["spring"]["stiffness_n_m"].as_float(), Some(2.5e4));
        assert_eq!(doc["axle"][1]["mass_kg"].as_float(), Some(7.5));
        assert_eq!(doc["axle"][0]["mass_kg"].as_float(), Some(2.0));
        let e = with(&[ov("sprin.stiffness_n_m", "1")], || apply(p, text.clone())).unwrap_err();
        assert!(e.field.contains("sprin.stiffness_n_m"));
        // A missing key of an existing table is added.
        let out = with(&[ov("spring.damping_n_s_m", "3.0")], || {
            apply(p, text.clone())
        })
        .unwrap();
        let doc: DocumentMut = out.parse().unwrap();
        assert_eq!(doc["spring"]["damping_n_s_m"].as_float(), Some(3.0));
        // Other files and other threads are untouched.
        assert_eq!(apply(p, text.clone()).unwrap(), text);
    }
}
