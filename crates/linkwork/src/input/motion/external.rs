//! A law evaluated by a function the engine does not own: the Python bindings build one
//! around a Python callable. In a description it is only a name, `{"type": "python",
//! "name": ...}`; the function is bound before compiling (`ExternalLaw::bind`).

use std::cell::RefCell;
use std::fmt;
use std::sync::{Arc, Mutex};

use serde::{Deserialize, Serialize};

/// f(t) -> (f, f', f''), or why it could not be computed.
pub type ExternalFn = Arc<dyn Fn(f64) -> Result<[f64; 3], String> + Send + Sync>;

thread_local! {
    /// (law name, t, why) of the last external law that failed on this thread (it then
    /// returned NaN): read back by the error report of the solve that met the NaN, which
    /// runs on the same thread.
    static FAILURE: RefCell<Option<(String, f64, String)>> = const { RefCell::new(None) };
}

/// Why the law `name` failed at t on this thread, if it did (and was not reported yet).
pub(crate) fn take_failure(name: &str, t: f64) -> Option<String> {
    FAILURE.with(|f| {
        let mut slot = f.borrow_mut();
        let mine = matches!(&*slot, Some((n, tf, _)) if n == name && tf.to_bits() == t.to_bits());
        if mine {
            slot.take().map(|(_, _, why)| why)
        } else {
            None
        }
    })
}

/// A law given by a function, with the last evaluation kept: a time step evaluates its
/// law for every Newton iteration, the velocity and the acceleration, all at the same t,
/// and the function is called once.
#[derive(Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExternalLaw {
    pub name: String,
    #[serde(skip)]
    func: Option<ExternalFn>,
    #[serde(skip)]
    last: LastCall,
}

impl ExternalLaw {
    /// A law named `name` evaluated by `func`.
    pub fn new(name: impl Into<String>, func: ExternalFn) -> ExternalLaw {
        ExternalLaw { name: name.into(), func: Some(func), last: LastCall::default() }
    }

    /// Gives the law its function (a description read from text has none).
    pub fn bind(&mut self, func: ExternalFn) {
        self.func = Some(func);
        self.last = LastCall::default();
    }

    pub fn is_bound(&self) -> bool {
        self.func.is_some()
    }

    pub(crate) fn check(&self) -> Result<(), String> {
        if self.func.is_none() {
            return Err(format!(
                "python law '{}' has no function: a model file cannot hold one (build the model \
                 from Python with the function, or write the law as an expression)",
                self.name
            ));
        }
        Ok(())
    }

    /// (f, f', f''); NaN if the function fails or is missing (the reason is kept for the
    /// error report: `take_failure`).
    #[inline]
    pub(crate) fn eval(&self, t: f64) -> [f64; 3] {
        if let Some(v) = self.last.get(t) {
            return v;
        }
        let result = match &self.func {
            Some(func) => func(t),
            None => Err("no function is bound to it".to_string()),
        };
        match result {
            Ok(v) => {
                self.last.set(t, v);
                v
            }
            Err(why) => {
                let why = format!("python law '{}' failed at t = {t}: {why}", self.name);
                FAILURE.with(|f| *f.borrow_mut() = Some((self.name.clone(), t, why)));
                // kept too: a step that tries another method at the same time (the general
                // path after the structured one) does not call the function again
                self.last.set(t, [f64::NAN; 3]);
                [f64::NAN; 3]
            }
        }
    }
}

impl fmt::Debug for ExternalLaw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ExternalLaw").field("name", &self.name).field("bound", &self.is_bound()).finish()
    }
}

impl PartialEq for ExternalLaw {
    /// The same name and the same function.
    fn eq(&self, other: &Self) -> bool {
        self.name == other.name
            && match (&self.func, &other.func) {
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                (None, None) => true,
                _ => false,
            }
    }
}

/// The last (t, value) computed; a clone starts empty.
#[derive(Default)]
struct LastCall(Mutex<Option<(f64, [f64; 3])>>);

impl LastCall {
    #[inline]
    fn get(&self, t: f64) -> Option<[f64; 3]> {
        let last = *self.0.lock().ok()?;
        last.filter(|(tl, _)| tl.to_bits() == t.to_bits()).map(|(_, v)| v)
    }

    #[inline]
    fn set(&self, t: f64, v: [f64; 3]) {
        if let Ok(mut last) = self.0.lock() {
            *last = Some((t, v));
        }
    }
}

impl Clone for LastCall {
    fn clone(&self) -> Self {
        LastCall::default()
    }
}
