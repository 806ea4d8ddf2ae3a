//! `ophis._ophis`, the native half of the `ophis` Python package: thin functions over
//! [`core`] that turn its results into Python objects and its errors into exceptions. The
//! public, documented API is the pure-Python `ophis/__init__.py`, which builds numpy arrays from
//! the flat buffers returned here.
//!
//! Two rules hold at this boundary: a panic in the library becomes a `RuntimeError`, never a
//! dead interpreter ([`guard`]); and a render releases the GIL and runs on its own thread while
//! the calling thread polls for signals and reports progress ([`render`]).

mod core;

use crate::core::{BsdfQuery, Counter, Error, FilmArgs, LoadedScene, Located, Source};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict, PyList, PyTuple};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

pyo3::create_exception!(
    _ophis,
    SceneError,
    PyValueError,
    "A scene that cannot be loaded: `str(e)` is `file:line:column: message`; the attributes \
     `file`, `line`, `column` and `message` hold the parts."
);

/// The exception for a library error.
fn to_py(py: Python<'_>, e: Error) -> PyErr {
    match e {
        Error::Scene(l) => scene_error(py, &l),
        Error::Io { message, missing } if missing => PyFileNotFoundError::new_err(message),
        Error::Io { message, .. } => PyOSError::new_err(message),
        Error::Value(m) => PyValueError::new_err(m),
    }
}

fn scene_error(py: Python<'_>, l: &Located) -> PyErr {
    let err = SceneError::new_err(format!("{}:{}:{}: {}", l.file, l.line, l.column, l.message));
    let v = err.value(py);
    // Setting attributes on a fresh exception instance cannot fail short of memory exhaustion;
    // if it did, the message still carries the location.
    let _ = v.setattr("file", &l.file);
    let _ = v.setattr("line", l.line);
    let _ = v.setattr("column", l.column);
    let _ = v.setattr("message", &l.message);
    err
}

/// Runs `f`, turning its error into an exception and a panic into a `RuntimeError`.
fn guard<T>(py: Python<'_>, f: impl FnOnce() -> Result<T, Error>) -> PyResult<T> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(|e| to_py(py, e)),
        Err(p) => Err(panic_error(p)),
    }
}

fn panic_error(p: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = p
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into());
    PyRuntimeError::new_err(format!(
        "internal error in ophis (a bug; please report it): {what}"
    ))
}

/// A loaded scene. The Python class `ophis.Scene` wraps it.
#[pyclass(frozen, module = "ophis._ophis")]
struct Scene {
    /// Locked by a render for its whole length (the seed is set on the scene itself).
    inner: Mutex<LoadedScene>,
    source: Source,
    defines: Vec<(String, String)>,
    #[pyo3(get)]
    width: u32,
    #[pyo3(get)]
    height: u32,
    #[pyo3(get)]
    spp: u32,
    #[pyo3(get)]
    name: String,
    #[pyo3(get)]
    scene_hash: String,
}

fn warnings_list<'py>(py: Python<'py>, ws: &[core::Warning]) -> PyResult<Bound<'py, PyList>> {
    let items: Vec<(String, u32, u32, String)> = ws
        .iter()
        .map(|w| (w.0.file.clone(), w.0.line, w.0.column, w.0.message.clone()))
        .collect();
    PyList::new(py, items)
}

fn load<'py>(
    py: Python<'py>,
    source: Source,
    defines: Vec<(String, String)>,
) -> PyResult<(Scene, Bound<'py, PyList>)> {
    let (loaded, warnings) = guard(py, || {
        // Meshes and images can take a while to read: other Python threads may run.
        py.detach(|| core::load(&source, &defines))
    })?;
    let (width, height) = loaded.resolution();
    let scene = Scene {
        width,
        height,
        spp: loaded.spp(),
        name: loaded.name().to_string(),
        scene_hash: loaded.hash_hex(),
        inner: Mutex::new(loaded),
        source,
        defines,
    };
    Ok((scene, warnings_list(py, &warnings)?))
}

/// Loads a scene file. Returns (scene, warnings as (file, line, column, message)).
#[pyfunction]
fn load_file<'py>(
    py: Python<'py>,
    path: PathBuf,
    defines: Vec<(String, String)>,
) -> PyResult<(Scene, Bound<'py, PyList>)> {
    load(py, Source::File(path), defines)
}

/// Loads a scene from XML text; `name` stands for the file in messages and relative paths.
#[pyfunction]
fn load_string<'py>(
    py: Python<'py>,
    xml: String,
    name: String,
    defines: Vec<(String, String)>,
) -> PyResult<(Scene, Bound<'py, PyList>)> {
    load(py, Source::Text { xml, name }, defines)
}

/// Loads the built-in Xenopeltis scene.
#[pyfunction]
fn load_xenopeltis<'py>(
    py: Python<'py>,
    defines: Vec<(String, String)>,
) -> PyResult<(Scene, Bound<'py, PyList>)> {
    load(py, core::xenopeltis(), defines)
}

/// How often the waiting thread looks for signals and reports progress.
const POLL: Duration = Duration::from_millis(100);

/// Renders on a worker thread with the GIL released. Returns (pixels as bytearray of f32,
/// height, width, channel names, metadata pairs, stats dict, exception or None): the exception
/// is what stopped the render early (KeyboardInterrupt, or one raised by `progress`); the image
/// then holds the samples taken, and the caller re-raises it after keeping the image.
#[pyfunction]
#[pyo3(signature = (scene, spp=None, seed=0, threads=None, progress=None, adaptive=None))]
fn render<'py>(
    py: Python<'py>,
    scene: &Bound<'py, Scene>,
    spp: Option<u32>,
    seed: u64,
    threads: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
    adaptive: Option<bool>,
) -> PyResult<Bound<'py, PyTuple>> {
    let sc = scene.get();
    let mut inner = sc.inner.try_lock().map_err(|_| {
        PyRuntimeError::new_err(
            "this scene is being rendered (by another thread); load it a second time to \
             render both at once",
        )
    })?;
    inner.set_seed(seed);
    inner.set_adaptive(adaptive);
    let loaded: &LoadedScene = &inner;
    let cancel = AtomicBool::new(false);
    let counter = Counter::default();
    let finished = AtomicBool::new(false);
    let mut stopped_by: Option<PyErr> = None;
    let joined = std::thread::scope(|s| {
        let worker = s.spawn(|| {
            let r = catch_unwind(AssertUnwindSafe(|| {
                core::render(loaded, spp, threads, &cancel, &counter)
            }));
            finished.store(true, Ordering::SeqCst);
            r
        });
        let mut reported = u64::MAX;
        loop {
            let done = py.detach(|| {
                let t0 = Instant::now();
                while !finished.load(Ordering::SeqCst) && t0.elapsed() < POLL {
                    std::thread::sleep(Duration::from_millis(5));
                }
                finished.load(Ordering::SeqCst)
            });
            if done || stopped_by.is_some() {
                // After a stop request, only wait for the tiles in flight.
                if done {
                    break;
                }
                continue;
            }
            let outcome = py.check_signals().and_then(|()| {
                let d = counter.done.load(Ordering::Relaxed);
                let total = counter.total.load(Ordering::Relaxed);
                // Before the first tile finishes the total is not known yet (0).
                match &progress {
                    Some(cb) if d != reported && total > 0 => {
                        reported = d;
                        cb.call1((d, total)).map(|_| ())
                    }
                    _ => Ok(()),
                }
            });
            if let Err(e) = outcome {
                cancel.store(true, Ordering::SeqCst);
                stopped_by = Some(e);
            }
        }
        worker.join()
    });
    let rendered = match joined {
        Ok(Ok(r)) => r.map_err(|e| to_py(py, e))?,
        Ok(Err(p)) | Err(p) => return Err(panic_error(p)),
    };
    if let (Some(cb), None) = (&progress, &stopped_by) {
        cb.call1((rendered.samples, rendered.samples))?;
    }
    let bytes: Vec<u8> = rendered.data.iter().flat_map(|v| v.to_ne_bytes()).collect();
    let stats = PyDict::new(py);
    stats.set_item("spp", rendered.spp_complete)?;
    stats.set_item("samples", rendered.samples)?;
    stats.set_item("seconds", rendered.seconds)?;
    stats.set_item("seed", seed)?;
    stats.set_item("stopped_early", rendered.stopped_early)?;
    let exc: Bound<'py, PyAny> = match stopped_by {
        Some(e) => e.into_value(py).into_bound(py).into_any(),
        None => py.None().into_bound(py),
    };
    (
        PyByteArray::new(py, &bytes),
        rendered.height,
        rendered.width,
        rendered.channels,
        rendered.metadata,
        stats,
        exc,
    )
        .into_pyobject(py)
}

/// Writes an RGB image (bytes of height × width × 3 native-endian f32) as EXR or PNG, with
/// the channels `extra_names` (bytes of one height × width f32 plane each, in order) beside
/// R, G, B in an EXR.
#[pyfunction]
#[pyo3(signature = (path, width, height, data, metadata, extra_names=Vec::new(), extra=None))]
#[allow(clippy::too_many_arguments)] // the Python signature, one argument per value
fn write(
    py: Python<'_>,
    path: PathBuf,
    width: usize,
    height: usize,
    data: &[u8],
    metadata: Vec<(String, String)>,
    extra_names: Vec<String>,
    extra: Option<&[u8]>,
) -> PyResult<()> {
    let plane = width.checked_mul(height).and_then(|n| n.checked_mul(4));
    let extra = extra.unwrap_or_default();
    if plane.and_then(|p| p.checked_mul(extra_names.len())) != Some(extra.len()) {
        return Err(PyValueError::new_err(format!(
            "{} bytes for {} extra {width} × {height} float32 channels",
            extra.len(),
            extra_names.len()
        )));
    }
    let planes: Vec<(String, Vec<f32>)> = extra_names
        .into_iter()
        .zip(extra.chunks_exact(plane.unwrap_or(1).max(1)))
        .map(|(n, b)| {
            let v = b
                .chunks_exact(4)
                .map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
                .collect();
            (n, v)
        })
        .collect();
    if width.checked_mul(height).and_then(|n| n.checked_mul(12)) != Some(data.len()) {
        return Err(PyValueError::new_err(format!(
            "{} bytes for a {width} × {height} RGB float32 image",
            data.len()
        )));
    }
    let rgb: Vec<f32> = data
        .chunks_exact(4)
        .map(|b| f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    guard(py, || {
        core::write_image(&path, width, height, &rgb, &planes, &metadata)
    })
}

/// Reads an image: (width, height, bytearray of f32 RGB, metadata pairs, bytearray of u64
/// samples per pixel or None).
#[pyfunction]
fn read<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyTuple>> {
    let img = guard(py, || core::read(&path))?;
    let rgb: Vec<u8> = img.rgb.iter().flat_map(|v| v.to_ne_bytes()).collect();
    let spp: Option<Bound<'py, PyByteArray>> = img.pixel_spp.map(|c| {
        let b: Vec<u8> = c.iter().flat_map(|v| v.to_ne_bytes()).collect();
        PyByteArray::new(py, &b)
    });
    (
        img.width,
        img.height,
        PyByteArray::new(py, &rgb),
        img.metadata,
        spp,
    )
        .into_pyobject(py)
}

/// Film reflectance: (R, T, Rs, Rp as flat lists, wavelengths outer; rgb per angle, flat).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[allow(clippy::type_complexity)]
fn thinfilm(
    py: Python<'_>,
    film_ior: String,
    thickness: f64,
    ext_ior: String,
    int_ior: Option<String>,
    int_eta: Option<f64>,
    int_k: Option<f64>,
    wavelengths: Vec<f64>,
    angles: Vec<f64>,
    stack: Option<String>,
) -> PyResult<(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>)> {
    let int_nk = match (int_eta, int_k) {
        (Some(n), Some(k)) => Some((n, k)),
        (None, None) => None,
        _ => {
            return Err(PyValueError::new_err(
                "a metal base needs both int_eta and int_k",
            ))
        }
    };
    let args = FilmArgs {
        film_ior: &film_ior,
        thickness_nm: thickness,
        stack: stack.as_deref(),
        ext_ior: &ext_ior,
        int_ior: int_ior.as_deref(),
        int_nk,
    };
    let t = guard(py, || core::thinfilm(&args, &wavelengths, &angles))?;
    Ok((t.r, t.t, t.r_s, t.r_p, t.rgb))
}

fn bsdf(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    id: &str,
    q: BsdfQuery,
    wavelengths: Option<Vec<f32>>,
    samples: usize,
    seed: u64,
) -> PyResult<Vec<(f64, f64)>> {
    let sc = scene.get();
    guard(py, || {
        py.detach(|| {
            core::bsdf_estimate(
                &sc.source,
                &sc.defines,
                id,
                q,
                wavelengths.as_deref(),
                samples,
                seed,
            )
        })
    })
}

/// Directional albedo of a scene's BSDF: (mean, standard error) per wavelength, or R, G, B.
#[pyfunction]
#[pyo3(signature = (scene, id, theta_i, wavelengths, samples, seed))]
fn bsdf_albedo(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    id: &str,
    theta_i: f32,
    wavelengths: Option<Vec<f32>>,
    samples: usize,
    seed: u64,
) -> PyResult<Vec<(f64, f64)>> {
    let q = BsdfQuery::Albedo { theta_i };
    bsdf(py, scene, id, q, wavelengths, samples, seed)
}

/// f·|cos θo| of a scene's BSDF: (mean, standard error) per wavelength, or R, G, B.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
#[pyo3(signature = (scene, id, theta_i, theta_o, phi_o, wavelengths, samples, seed))]
fn bsdf_eval(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    id: &str,
    theta_i: f32,
    theta_o: f32,
    phi_o: f32,
    wavelengths: Option<Vec<f32>>,
    samples: usize,
    seed: u64,
) -> PyResult<Vec<(f64, f64)>> {
    let q = BsdfQuery::Eval {
        theta_i,
        theta_o,
        phi_o,
    };
    bsdf(py, scene, id, q, wavelengths, samples, seed)
}

/// Raises a Rust panic, to test that it arrives as a `RuntimeError`.
#[pyfunction]
fn _panic(py: Python<'_>) -> PyResult<()> {
    guard(py, || -> Result<(), Error> {
        panic!("deliberate test panic")
    })
}

#[pymodule]
fn _ophis(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add_class::<Scene>()?;
    m.add_function(wrap_pyfunction!(load_file, m)?)?;
    m.add_function(wrap_pyfunction!(load_string, m)?)?;
    m.add_function(wrap_pyfunction!(load_xenopeltis, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(thinfilm, m)?)?;
    m.add_function(wrap_pyfunction!(bsdf_albedo, m)?)?;
    m.add_function(wrap_pyfunction!(bsdf_eval, m)?)?;
    m.add_function(wrap_pyfunction!(_panic, m)?)?;
    Ok(())
}
