//! The library's errors as Python exceptions (classes in python/towride/_errors.py): an
//! input error keeps its file, line, column and field (as the CLI prints them,
//! `towride_mbs::input::InputError`'s Display), every other error is a `TowrideError`
//! with the CLI's message.

use pyo3::prelude::*;

use towride_app::error::{Error, SceneError, ValidateError};
use towride_mbs::input::InputError;

/// The input error inside `e`, wherever the layers wrapped it.
fn input_error(e: &Error) -> Option<&InputError> {
    match e {
        Error::Input(i)
        | Error::Scene(SceneError::Input(i))
        | Error::Validate(ValidateError::Input(i))
        | Error::Flex(towride_mbs::flex::FlexError::Input(i))
        | Error::Road(towride_mbs::road::RoadError::Input(i)) => Some(i),
        Error::Validate(ValidateError::Simulation(inner)) => input_error(inner),
        _ => None,
    }
}

/// `e` as an instance of `towride.InputError` or `towride.TowrideError`.
pub fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let m = py.import("towride._errors")?;
        let obj = match input_error(&e) {
            Some(i) => m.getattr("InputError")?.call1((
                e.to_string(),
                i.file.display().to_string(),
                i.line,
                i.column,
                i.field.clone(),
                i.message.clone(),
            ))?,
            None => m.getattr("TowrideError")?.call1((e.to_string(),))?,
        };
        Ok(PyErr::from_value(obj))
    })();
    made.unwrap_or_else(|err| err)
}
