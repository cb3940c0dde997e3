//! A run's options by name, as Python passes them (`method="bdf", rtol=1e-8`): each
//! checked against the options that run takes, the defaults those of the Rust API.

use filippov_runtime::{LieSdirk, Method, NonSmoothMethod, Options, Output, Rkmk5};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::as_f64;

/// The options every run takes besides its method.
pub struct Common {
    /// Start time (default 0).
    pub t0: f64,
    /// Which rows to keep (`times=[…]`, `every=k`; default every step).
    pub output: Output,
    /// Constant applied generalised forces (`tau=[…]`; default none).
    pub tau: Option<Vec<f64>>,
}

const SMOOTH: &[&str] = &[
    "method",
    "rtol",
    "atol",
    "h",
    "h0",
    "h_max",
    "max_steps",
    "t0",
    "times",
    "every",
    "tau",
];
const NONSMOOTH: &[&str] = &[
    "method",
    "smooth",
    "rtol",
    "atol",
    "h",
    "h0",
    "h_max",
    "theta",
    "max_steps",
    "t0",
    "times",
    "every",
    "tau",
];

/// The options as `(name, value)`, each a known one.
fn entries<'py>(
    call: &str,
    known: &[&str],
    opts: Option<&Bound<'py, PyDict>>,
) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    let mut out = Vec::new();
    if let Some(d) = opts {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            if !known.contains(&k.as_str()) {
                return Err(PyTypeError::new_err(format!(
                    "{call}() got an unexpected option `{k}`; its options are {}",
                    known.join(", ")
                )));
            }
            out.push((k, v));
        }
    }
    Ok(out)
}

fn get<'py, T: FromPyObjectOwned<'py>>(
    call: &str,
    entries: &[(String, Bound<'py, PyAny>)],
    name: &str,
) -> PyResult<Option<T>> {
    match entries.iter().find(|(k, _)| k == name) {
        None => Ok(None),
        Some((_, v)) if v.is_none() => Ok(None),
        Some((_, v)) => v.extract::<T>().map(Some).map_err(|_| {
            let got = v
                .get_type()
                .name()
                .map_or_else(|_| "?".to_string(), |n| n.to_string());
            PyTypeError::new_err(format!(
                "{call}(): option `{name}` must be a {}, got {got}",
                std::any::type_name::<T>()
                    .rsplit("::")
                    .next()
                    .unwrap_or("value")
            ))
        }),
    }
}

fn common<'py>(call: &str, n: usize, e: &[(String, Bound<'py, PyAny>)]) -> PyResult<Common> {
    let t0 = get::<f64>(call, e, "t0")?.unwrap_or(0.0);
    let times = match e.iter().find(|(k, _)| k == "times") {
        Some((_, v)) if !v.is_none() => Some(as_f64(v)?.as_slice()?.to_vec()),
        _ => None,
    };
    let every = get::<usize>(call, e, "every")?;
    let output = match (times, every) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(format!(
                "{call}(): give `times` or `every`, not both"
            )));
        }
        (Some(t), None) => Output::Times(t),
        (None, Some(k)) => Output::Every(k),
        (None, None) => Output::Steps,
    };
    let tau = match e.iter().find(|(k, _)| k == "tau") {
        Some((_, v)) if !v.is_none() => {
            let t = as_f64(v)?.as_slice()?.to_vec();
            if t.len() != n {
                return Err(PyValueError::new_err(format!(
                    "{call}(): tau has {} values; the scene has {n} coordinates",
                    t.len()
                )));
            }
            Some(t)
        }
        _ => None,
    };
    Ok(Common { t0, output, tau })
}

/// The tolerances and step limits, over `base`.
fn adaptive<'py>(
    call: &str,
    e: &[(String, Bound<'py, PyAny>)],
    base: Options,
) -> PyResult<Options> {
    let mut o = base;
    if let Some(x) = get::<f64>(call, e, "rtol")? {
        o.rtol = x;
    }
    if let Some(x) = get::<f64>(call, e, "atol")? {
        o.atol = x;
    }
    if let Some(x) = get::<f64>(call, e, "h0")? {
        o.h0 = Some(x);
    }
    if let Some(x) = get::<f64>(call, e, "h_max")? {
        o.h_max = x;
    }
    if let Some(x) = get::<usize>(call, e, "max_steps")? {
        o.max_steps = x;
    }
    Ok(o)
}

/// A smooth method by name: `dopri5`, `sdirk4`, `bdf` (adaptive) or `rk4` (fixed step `h`).
fn smooth_method<'py>(
    call: &str,
    name: &str,
    e: &[(String, Bound<'py, PyAny>)],
    base: Options,
) -> PyResult<Method> {
    let o = adaptive(call, e, base)?;
    Ok(match name.to_ascii_lowercase().as_str() {
        "dopri5" => Method::Dopri5(o),
        "sdirk4" => Method::Sdirk4(o),
        "bdf" => Method::Bdf(o),
        "rk4" => match get::<f64>(call, e, "h")? {
            Some(h) => Method::Rk4 { h },
            None => {
                return Err(PyValueError::new_err(format!(
                    "{call}(): method `rk4` takes a fixed step; give it as h=…"
                )));
            }
        },
        other => {
            return Err(PyValueError::new_err(format!(
                "{call}(): no method `{other}`; the smooth methods are dopri5, sdirk4, bdf and rk4"
            )));
        }
    })
}

/// `solve`'s options: the method (default DOPRI5 at the Rust defaults, rtol 1e-6,
/// atol 1e-9) and the common ones.
pub fn smooth(n: usize, opts: Option<&Bound<'_, PyDict>>) -> PyResult<(Method, Common)> {
    let call = "solve";
    let e = entries(call, SMOOTH, opts)?;
    let name = get::<String>(call, &e, "method")?.unwrap_or_else(|| "dopri5".into());
    let method = smooth_method(call, &name, &e, Options::default())?;
    Ok((method, common(call, n, &e)?))
}

/// `solve_nonsmooth`'s (and `integrator`'s) options: `method="event_driven"` (default:
/// DOPRI5 at rtol 1e-8, atol 1e-10 between events, `smooth=` another smooth method) or
/// `"time_stepping"` (fixed step `h`, `theta` default 1: implicit Euler).
pub fn nonsmooth(
    call: &str,
    n: usize,
    opts: Option<&Bound<'_, PyDict>>,
) -> PyResult<(NonSmoothMethod, Common)> {
    let e = entries(call, NONSMOOTH, opts)?;
    let name = get::<String>(call, &e, "method")?.unwrap_or_else(|| "event_driven".into());
    let method = match name.to_ascii_lowercase().as_str() {
        "event_driven" => {
            let base = match NonSmoothMethod::default() {
                NonSmoothMethod::EventDriven(m) => m.options(),
                _ => Options::default(),
            };
            let smooth = get::<String>(call, &e, "smooth")?.unwrap_or_else(|| "dopri5".into());
            NonSmoothMethod::EventDriven(smooth_method(call, &smooth, &e, base)?)
        }
        "time_stepping" => {
            let Some(h) = get::<f64>(call, &e, "h")? else {
                return Err(PyValueError::new_err(format!(
                    "{call}(): time_stepping takes a fixed step; give it as h=…"
                )));
            };
            let theta = get::<f64>(call, &e, "theta")?.unwrap_or(1.0);
            NonSmoothMethod::TimeStepping { h, theta }
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "{call}(): no method `{other}`; the non-smooth methods are event_driven \
                 (smooth=dopri5, sdirk4, bdf or rk4 between events) and time_stepping"
            )));
        }
    };
    Ok((method, common(call, n, &e)?))
}

/// A Lie-group method (scenes with spherical or free joints).
pub enum LieMethod {
    Rkmk5(Rkmk5),
    Sdirk(LieSdirk),
}

/// `solve`'s options for a scene with spherical or free joints: `method="rkmk5"`
/// (default: explicit Munthe-Kaas Dormand–Prince) or `"lie_sdirk"` (stiff), adaptive at
/// the Rust defaults (rtol 1e-6, atol 1e-9), or fixed steps with `h=…`; and the common
/// ones.
pub fn lie(n: usize, opts: Option<&Bound<'_, PyDict>>) -> PyResult<(LieMethod, Common)> {
    let call = "solve";
    // The same options as on a vector space; `h` makes either method's steps fixed.
    let e = entries(call, SMOOTH, opts)?;
    let name = get::<String>(call, &e, "method")?.unwrap_or_else(|| "rkmk5".into());
    let h = get::<f64>(call, &e, "h")?;
    let method = match name.to_ascii_lowercase().as_str() {
        "rkmk5" => {
            let base = h.map_or_else(|| Rkmk5::new(Options::default()), Rkmk5::fixed);
            LieMethod::Rkmk5(Rkmk5 {
                options: adaptive(call, &e, base.options)?,
                fixed_step: h,
            })
        }
        "lie_sdirk" => {
            let base = h.map_or_else(|| LieSdirk::new(Options::default()), LieSdirk::fixed);
            LieMethod::Sdirk(LieSdirk {
                options: adaptive(call, &e, base.options)?,
                fixed_step: h,
            })
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "{call}(): no method `{other}`; a scene with spherical or free joints is \
                 integrated on its Lie group by rkmk5 (explicit, the default) or lie_sdirk \
                 (stiff), adaptive, or with fixed steps given as h=…"
            )));
        }
    };
    Ok((method, common(call, n, &e)?))
}
