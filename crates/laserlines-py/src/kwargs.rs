//! Keyword arguments as the values of a params table, and a params table back as a dict:
//! `bool`, `int`, `float`, `str`, lists or tuples of them, dicts for nested parameters.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// The keyword arguments as a params table; `None` gives an empty table.
///
/// # Errors
/// `TypeError` naming the parameter whose value has no params-file form.
pub fn to_table(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<toml::Table> {
    let mut table = toml::Table::new();
    if let Some(kwargs) = kwargs {
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let v = to_value(&value).map_err(|found| {
                PyTypeError::new_err(format!(
                    "parameter {key}: expected a bool, int, float, str, list or dict, found {found}"
                ))
            })?;
            table.insert(key, v);
        }
    }
    Ok(table)
}

/// One value; `Err` with the name of the Python type that has no params-file form.
fn to_value(v: &Bound<'_, PyAny>) -> Result<toml::Value, String> {
    let type_name = || {
        v.get_type()
            .name()
            .map_or_else(|_| "an object".to_owned(), |n| n.to_string())
    };
    // bool before int: True is an int in Python.
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if v.cast::<PyInt>().is_ok() {
        return int_value(v);
    }
    if let Ok(f) = v.cast::<PyFloat>() {
        return Ok(toml::Value::Float(f.value()));
    }
    if let Ok(s) = v.cast::<PyString>() {
        return s
            .extract::<String>()
            .map(toml::Value::String)
            .map_err(|_| type_name());
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (key, value) in d.iter() {
            let key: String = key
                .extract()
                .map_err(|_| "a dict with keys other than str".to_owned())?;
            table.insert(key, to_value(&value)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if v.cast::<PyList>().is_ok() || v.cast::<PyTuple>().is_ok() {
        let items: Vec<Bound<'_, PyAny>> = v
            .try_iter()
            .map_err(|_| type_name())?
            .collect::<PyResult<_>>()
            .map_err(|_| type_name())?;
        return items
            .iter()
            .map(to_value)
            .collect::<Result<_, _>>()
            .map(toml::Value::Array);
    }
    // numpy arrays and scalars as the Python lists and numbers `tolist` gives (an int64 an
    // int, not a float).
    if v.hasattr("dtype").unwrap_or(false)
        && let Ok(plain) = v.call_method0("tolist")
        && !plain.hasattr("dtype").unwrap_or(true)
    {
        return to_value(&plain);
    }
    // Other integers (anything with `__index__`) are ints, other numbers floats.
    if v.hasattr("__index__").unwrap_or(false)
        && let Ok(i) = v.call_method0("__index__")
    {
        return int_value(&i);
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    Err(type_name())
}

/// A Python int as a params value: params files hold integers of 64 bits, signed.
fn int_value(v: &Bound<'_, PyAny>) -> Result<toml::Value, String> {
    v.extract::<i64>().map(toml::Value::Integer).map_err(|_| {
        format!("{v}, an int outside -2**63..2**63 (params hold 64-bit signed integers)")
    })
}

/// A params table as a dict (nested tables as dicts, arrays as lists).
///
/// # Errors
/// Only when Python cannot allocate.
pub fn to_dict<'py>(py: Python<'py>, table: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (key, value) in table {
        dict.set_item(key, from_value(py, value)?)?;
    }
    Ok(dict)
}

fn from_value<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(f) => PyFloat::new(py, *f).into_any(),
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| from_value(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => to_dict(py, t)?.into_any(),
    })
}
