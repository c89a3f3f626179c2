//! `critspeed._native`: the Python extension module, thin over `critspeed::api` (the functions
//! the command line calls). It converts arguments and results and manages the GIL and Ctrl-C;
//! it computes nothing itself. The public Python API, with its docstrings, is
//! `critspeed/__init__.py`.
//!
//! Every computing function returns `(result, warnings)`: the messages the command line prints
//! as `warning: …` (values outside their plausible ranges, figures written as a note), which
//! the Python layer issues as `critspeed.CritspeedWarning`.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use critspeed::api::{self, files, Column, Failure, Hooks, Prepared, SimulateRequest, Source};
use critspeed::study::units::Dimension;
use critspeed::sweep::{Shard, SweepOptions};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyByteArray, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::Value;

create_exception!(
    critspeed,
    StudyError,
    PyValueError,
    "A bad study or argument: the message names the key, the value and the rule."
);
create_exception!(
    critspeed,
    ComputationError,
    PyRuntimeError,
    "A numerical failure (e.g. a contact solve that does not converge), or an output failure."
);

fn raise(f: Failure) -> PyErr {
    match f {
        Failure::User(_) => StudyError::new_err(f.message()),
        Failure::Compute(_) => ComputationError::new_err(f.message()),
    }
}

fn user(message: String) -> PyErr {
    StudyError::new_err(message)
}

/// A study dict's value as TOML, the one conversion of a dict study (the library reads the
/// TOML as it reads a file). `key` is the dotted path, named in every refusal.
fn to_toml(o: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    if o.is_none() {
        return Err(user(format!(
            "{key} = None: a study value must be a number, a string, a boolean, a list or a table"
        )));
    }
    if let Ok(b) = o.cast::<PyBool>() {
        return Ok(toml::Value::Boolean(b.is_true()));
    }
    if o.is_instance_of::<PyInt>() {
        let i: i64 = o
            .extract()
            .map_err(|_| user(format!("{key} = {o}: integer out of range")))?;
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(f) = o.cast::<PyFloat>() {
        return match f.value() {
            v if v.is_finite() => Ok(toml::Value::Float(v)),
            v => Err(user(format!("{key} = {v}: must be finite"))),
        };
    }
    if let Ok(s) = o.cast::<PyString>() {
        return Ok(toml::Value::String(s.extract::<String>()?));
    }
    if let Ok(d) = o.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, v) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| user(format!("{key}: keys must be strings, found {k:?}")))?;
            let sub = if key.is_empty() {
                k.clone()
            } else {
                format!("{key}.{k}")
            };
            t.insert(k, to_toml(&v, &sub)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if o.is_instance_of::<PyList>() || o.is_instance_of::<PyTuple>() {
        let mut a = Vec::new();
        for (i, v) in o.try_iter()?.enumerate() {
            a.push(to_toml(&v?, &format!("{key}[{i}]"))?);
        }
        return Ok(toml::Value::Array(a));
    }
    // numpy scalars and other numbers
    if let Ok(v) = o.extract::<f64>() {
        return to_toml(&PyFloat::new(o.py(), v), key);
    }
    Err(user(format!(
        "{key} = {o}: a study value must be a number, a string, a boolean, a list or a dict"
    )))
}

/// JSON as Python objects: objects become dicts, numbers keep their exact value and type.
fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// CSV columns as `[(name, kind, data)]`: kind "f64"/"bool" with a bytearray of native
/// f64/u8 values (numpy reads it without a copy), "optbool"/"str" with a list.
fn columns_py<'py>(
    py: Python<'py>,
    csv: &str,
    kinds: &[(&str, api::Kind)],
) -> PyResult<Bound<'py, PyList>> {
    let cols = api::columns(csv, kinds).map_err(raise)?;
    let mut out = Vec::with_capacity(cols.len());
    for (name, col) in cols {
        let (kind, data): (&str, Bound<'py, PyAny>) = match col {
            Column::F64(v) => {
                let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_ne_bytes()).collect();
                ("f64", PyByteArray::new(py, &bytes).into_any())
            }
            Column::Bool(v) => {
                let bytes: Vec<u8> = v.iter().map(|b| u8::from(*b)).collect();
                ("bool", PyByteArray::new(py, &bytes).into_any())
            }
            Column::OptBool(v) => ("optbool", v.into_pyobject(py)?.into_any()),
            Column::Text(v) => ("str", v.into_pyobject(py)?.into_any()),
        };
        out.push((name, kind, data));
    }
    PyList::new(py, out)
}

/// The study as the library's [`Source`]: `kind` is "path", "text" or "dict".
fn source(kind: &str, value: &Bound<'_, PyAny>) -> PyResult<Source> {
    match kind {
        "path" => Source::file(&value.extract::<PathBuf>()?).map_err(raise),
        "text" => Ok(Source::text(&value.extract::<String>()?, "<TOML text>")),
        "dict" => match to_toml(value, "")? {
            toml::Value::Table(t) => Source::table(&t, "<dict>").map_err(raise),
            _ => Err(user("<dict>: a study must be a table (a dict)".into())),
        },
        _ => Err(PyValueError::new_err(format!(
            "unknown study kind {kind:?}"
        ))),
    }
}

/// A plan prepared for analyses, its plausibility warnings taken into `warnings`.
fn prepare(src: &Source, warnings: &mut Vec<String>) -> Result<Prepared, Failure> {
    let plan = src.plan()?;
    warnings.extend(plan.warnings.iter().map(ToString::to_string));
    Prepared::new(plan)
}

/// Writes the files `make` renders into `out/<name>/` when `out` is given (rendering the
/// figures costs time: nothing is rendered without `out`); figures written as a note add
/// their warnings.
fn save(
    out: Option<&PathBuf>,
    name: &str,
    warnings: &mut Vec<String>,
    make: impl FnOnce() -> Result<files::Output, Failure>,
) -> Result<(), Failure> {
    if let Some(root) = out {
        let dir = files::folder(root, name)?;
        let o = make()?;
        files::write(&dir, &o, &mut |_| {})?;
        warnings.extend(o.warnings);
    }
    Ok(())
}

/// Runs `f` with the GIL released. A `long` computation runs on a worker thread while this
/// thread checks for signals (Ctrl-C) every 50 ms: on a signal the cancellation flag is raised,
/// the worker stops at its next check (between continuation steps, sweep points, simulated
/// speeds, uncertainty evaluations) and the signal's exception (KeyboardInterrupt) is raised.
fn call<T: Send>(
    py: Python<'_>,
    long: bool,
    f: impl FnOnce(api::Cancel<'_>) -> Result<T, Failure> + Send,
) -> PyResult<T> {
    if !long {
        return py.detach(|| f(None)).map_err(raise);
    }
    let flag = AtomicBool::new(false);
    let cancel = || flag.load(Ordering::Relaxed);
    let (done, result) = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = mpsc::channel();
            let worker = scope.spawn(move || {
                let r = f(Some(&cancel));
                let _ = tx.send(());
                r
            });
            let mut signal = None;
            loop {
                match rx.recv_timeout(Duration::from_millis(50)) {
                    Err(mpsc::RecvTimeoutError::Timeout) if signal.is_none() => {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            flag.store(true, Ordering::Relaxed);
                            signal = Some(e);
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    _ => break,
                }
            }
            (signal, worker.join())
        })
    });
    match (done, result) {
        (Some(e), _) => Err(e),
        (None, Ok(r)) => r.map_err(raise),
        (None, Err(_)) => Err(ComputationError::new_err(
            "internal error: the computation panicked",
        )),
    }
}

/// The library's version.
#[pyfunction]
fn version() -> &'static str {
    api::VERSION
}

/// A quantity argument: a number (SI) or a string with a unit of `dim`
/// ("speed", "length", "time").
#[pyfunction]
fn quantity(name: &str, text: &str, dim: &str) -> PyResult<f64> {
    let d = match dim {
        "speed" => Dimension::Speed,
        "length" => Dimension::Length,
        "time" => Dimension::Time,
        _ => return Err(PyValueError::new_err(format!("unknown dimension {dim:?}"))),
    };
    api::quantity(name, text, d).map_err(raise)
}

/// The resolved plan (and the [sweep]/[trade] sections) as a dict, with `warnings` when a
/// value lies outside its plausible range.
#[pyfunction]
fn check<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let src = source(kind, value)?;
    let json = call(py, false, |_| api::check_json(&api::check(&src)?))?;
    to_py(py, &json)
}

/// `linear --json`'s object.
#[pyfunction]
#[pyo3(signature = (kind, value, out=None))]
fn linear<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    let src = source(kind, value)?;
    let (json, w) = call(py, false, |_| {
        let mut w = Vec::new();
        let p = prepare(&src, &mut w)?;
        let r = api::linear(&p)?;
        save(out.as_ref(), &p.plan().name, &mut w, || files::linear(&r))?;
        Ok((critspeed::output::linear_json(&r), w))
    })?;
    Ok((to_py(py, &json)?, w))
}

/// `bifurcation --json`'s object and the columns of branch.csv.
#[pyfunction]
#[pyo3(signature = (kind, value, out=None))]
fn bifurcation<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (r, w) = call(py, true, |cancel| {
        let mut w = Vec::new();
        let p = prepare(&src, &mut w)?;
        let hooks = Hooks {
            progress: None,
            cancel,
            branches: None,
        };
        // as `critspeed bifurcation`: a study with an `[attractors]` section runs the search
        // too, and the report carries the one V_NL of both
        let (r, search) = api::nonlinear(&p, || api::bifurcation(&p, hooks), cancel, None)?;
        save(out.as_ref(), &r.study, &mut w, || files::bifurcation(&r))?;
        if let Some(a) = &search {
            save(out.as_ref(), &r.study, &mut w, || files::attractors(a, &r))?;
        }
        Ok((r, w))
    })?;
    let json = critspeed::output::bifurcation_json(&r);
    let csv = critspeed::output::branch_csv(&r);
    Ok((
        to_py(py, &json)?,
        columns_py(py, &csv, api::kinds::BRANCH)?,
        w,
    ))
}

/// `curve --json`'s object and the columns of curve.csv.
#[pyfunction]
#[pyo3(signature = (kind, value, out=None))]
fn curve<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (r, w) = call(py, true, |cancel| {
        let mut w = Vec::new();
        let study = api::curve::curve_study(&src)?;
        let r = api::curve::curve(&study, cancel)?;
        save(out.as_ref(), &r.study, &mut w, || api::curve::files(&r))?;
        Ok((r, w))
    })?;
    let json = critspeed::output::curve_json(&r);
    let csv = critspeed::output::curve_csv(&r);
    Ok((
        to_py(py, &json)?,
        columns_py(py, &csv, api::kinds::CURVE)?,
        w,
    ))
}

/// `attractors --json`'s object (with the one V_NL of the continuation and the search) and the
/// columns of attractors.csv.
#[pyfunction]
#[pyo3(signature = (kind, value, out=None))]
fn attractors<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (json, csv, w) = call(py, true, |cancel| {
        let mut w = Vec::new();
        let p = prepare(&src, &mut w)?;
        let hooks = Hooks {
            progress: None,
            cancel,
            branches: None,
        };
        let (r, b) = api::attractors(&p, hooks, None)?;
        save(out.as_ref(), &r.study, &mut w, || {
            let mut o = files::bifurcation(&b)?;
            let a = files::attractors(&r, &b)?;
            o.files.extend(a.files);
            o.warnings.extend(a.warnings);
            Ok(o)
        })?;
        Ok((
            critspeed::output::attractors_json(&r, &b),
            critspeed::output::attractors_csv(&r),
            w,
        ))
    })?;
    Ok((
        to_py(py, &json)?,
        columns_py(py, &csv, api::kinds::ATTRACTORS)?,
        w,
    ))
}

/// The columns of simulate.csv.
#[pyfunction]
#[pyo3(signature = (kind, value, speeds, y0, duration, dt, out=None, start_from=None, kick=None, rtol=None))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    speeds: Vec<f64>,
    y0: f64,
    duration: f64,
    dt: f64,
    out: Option<PathBuf>,
    start_from: Option<String>,
    kick: Option<Vec<String>>,
    rtol: Option<f64>,
) -> PyResult<(Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let req = SimulateRequest {
        speeds,
        y0,
        duration,
        dt,
        from: start_from
            .as_deref()
            .map(api::attractor_start)
            .transpose()
            .map_err(raise)?,
        kicks: kick.unwrap_or_default(),
        rtol,
    };
    let (csv, w) = call(py, true, |cancel| {
        let mut w = Vec::new();
        let p = prepare(&src, &mut w)?;
        let runs = api::simulate(&p, &req, &|_| {}, cancel)?;
        let name = &p.plan().name;
        save(out.as_ref(), name, &mut w, || {
            Ok(files::simulate(name, &runs))
        })?;
        Ok((critspeed::output::simulate_csv(&runs), w))
    })?;
    Ok((columns_py(py, &csv, api::kinds::NUMBERS)?, w))
}

/// The columns of sweep.csv. With `out`, resumable like the CLI (records file in out/<name>/).
#[pyfunction]
#[pyo3(signature = (kind, value, threads=None, out=None))]
fn sweep<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    threads: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (csv, w) = call(py, true, |cancel| {
        let study = src.sweep_study()?;
        let mut w = api::sweep_warnings(&study);
        let name = &study.base.name;
        let records = match &out {
            Some(root) => Some(files::folder(root, name)?.join(Shard::ALL.records_file())),
            None => None,
        };
        let opts = SweepOptions {
            threads,
            shard: Shard::ALL,
            records,
        };
        let rows = api::sweep(&study, &opts, None, cancel)?.rows;
        save(out.as_ref(), name, &mut w, || {
            Ok(files::sweep(&study, &rows))
        })?;
        Ok((critspeed::sweep::sweep_csv(&study.spec.axes, &rows), w))
    })?;
    Ok((columns_py(py, &csv, api::kinds::SWEEP)?, w))
}

/// `uncertainty --json`'s object and the columns of uncertainty.csv. With `out`, resumable like
/// the CLI (records file in out/<name>/).
#[pyfunction]
#[pyo3(signature = (kind, value, threads=None, out=None))]
fn uncertainty<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    threads: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (json, csv, w) = call(py, true, |cancel| {
        let study = src.uncertainty_study()?;
        // the CLI's warnings: the base plan's (the sampled values are not checked one by one)
        let mut w: Vec<String> = study
            .sweep
            .base
            .warnings
            .iter()
            .map(ToString::to_string)
            .collect();
        let name = &study.sweep.base.name;
        let records = match &out {
            Some(root) => Some(
                files::folder(root, name)?
                    .join(Shard::ALL.records_file_of(critspeed::uncertainty::RECORDS_STEM)),
            ),
            None => None,
        };
        let opts = SweepOptions {
            threads,
            shard: Shard::ALL,
            records,
        };
        let rows = api::uncertainty(&study, &opts, None, cancel)?.rows;
        let report = critspeed::uncertainty::report(&study, &rows);
        save(out.as_ref(), name, &mut w, || {
            files::uncertainty(&study, &report, &rows)
        })?;
        let json = serde_json::to_value(&report)
            .map_err(|e| Failure::Compute(anyhow::anyhow!("uncertainty.json: {e}")))?;
        Ok((
            json,
            critspeed::uncertainty::uncertainty_csv(&study, &rows),
            w,
        ))
    })?;
    Ok((
        to_py(py, &json)?,
        columns_py(py, &csv, api::kinds::UNCERTAINTY)?,
        w,
    ))
}

/// `conicity --json`'s object, from a study or a Δr table (`y`, `dr` in metres).
#[pyfunction]
#[pyo3(signature = (kind, value, amplitudes=None, out=None, table=None))]
fn conicity<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    amplitudes: Option<Vec<f64>>,
    out: Option<PathBuf>,
    table: Option<(Vec<f64>, Vec<f64>)>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    let input = match table {
        Some((y, dr)) => Err((y, dr)),
        None => Ok(source(kind, value)?),
    };
    let (json, w) = call(py, false, |_| {
        let mut w = Vec::new();
        let (name, dr) = match input {
            Ok(src) => {
                let p = prepare(&src, &mut w)?;
                (p.plan().name.clone(), api::delta_r(&p)?)
            }
            Err((y, dr)) => {
                if y.len() != dr.len() {
                    return Err(Failure::User(anyhow::anyhow!(
                        "delta_r: y has {} values, dr {}; they must pair up",
                        y.len(),
                        dr.len()
                    )));
                }
                let pts = y.into_iter().zip(dr).collect();
                let t = critspeed::conicity::DeltaR::new(pts, "delta_r")
                    .map_err(|e| Failure::User(e.into()))?;
                ("delta_r".to_string(), t)
            }
        };
        let explicit = amplitudes.is_some();
        let amps = amplitudes.unwrap_or_else(api::default_amplitudes);
        let (results, _) = api::conicity(&dr, &amps, explicit)?;
        save(out.as_ref(), &name, &mut w, || {
            Ok(files::conicity(&name, &results))
        })?;
        Ok((api::conicity_json(&results), w))
    })?;
    Ok((to_py(py, &json)?, w))
}

/// The columns of geometry.csv.
#[pyfunction]
#[pyo3(signature = (kind, value, out=None))]
fn geometry<'py>(
    py: Python<'py>,
    kind: &str,
    value: &Bound<'py, PyAny>,
    out: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyList>, Vec<String>)> {
    let src = source(kind, value)?;
    let (csv, w) = call(py, false, |_| {
        let mut w = Vec::new();
        let g = api::geometry(&prepare(&src, &mut w)?);
        save(out.as_ref(), &g.study, &mut w, || Ok(files::geometry(&g)))?;
        Ok((critspeed::output::geometry_csv(&g), w))
    })?;
    Ok((columns_py(py, &csv, api::kinds::NUMBERS)?, w))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("StudyError", m.py().get_type::<StudyError>())?;
    m.add("ComputationError", m.py().get_type::<ComputationError>())?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    m.add_function(wrap_pyfunction!(quantity, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(linear, m)?)?;
    m.add_function(wrap_pyfunction!(bifurcation, m)?)?;
    m.add_function(wrap_pyfunction!(curve, m)?)?;
    m.add_function(wrap_pyfunction!(attractors, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(uncertainty, m)?)?;
    m.add_function(wrap_pyfunction!(conicity, m)?)?;
    m.add_function(wrap_pyfunction!(geometry, m)?)?;
    Ok(())
}
