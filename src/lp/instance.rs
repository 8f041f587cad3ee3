//! HiGHS instances reused: one model after another on the same instance,
//! a few kept per thread. Creating an instance (its options' and info's
//! records) was about 5% of the CPU of `generate mixed 20`, whose 400
//! pieces each built one. The highs crate makes a new instance for every
//! problem and names columns by handles only it can make, so models are
//! passed here in HiGHS' own row-wise form, their columns by index.

use crate::error::{Error, Result};
use highs_sys::HighsInt;

/// A column of a model: its index in HiGHS.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Col(usize);

impl Col {
    pub(crate) fn index(self) -> usize {
        self.0
    }
}

/// A model being written: columns, then rows over them.
#[derive(Default)]
pub(crate) struct Problem {
    cost: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    row_lower: Vec<f64>,
    row_upper: Vec<f64>,
    starts: Vec<HighsInt>,
    index: Vec<HighsInt>,
    value: Vec<f64>,
}

impl Problem {
    pub(crate) fn add_column(&mut self, cost: f64, (lower, upper): (f64, f64)) -> Col {
        self.cost.push(cost);
        self.lower.push(lower);
        self.upper.push(upper);
        Col(self.cost.len() - 1)
    }

    pub(crate) fn add_row(
        &mut self,
        (lower, upper): (f64, f64),
        terms: impl IntoIterator<Item = (Col, f64)>,
    ) {
        self.starts.push(self.index.len() as HighsInt);
        for (c, v) in terms {
            self.index.push(c.0 as HighsInt);
            self.value.push(v);
        }
        self.row_lower.push(lower);
        self.row_upper.push(upper);
    }

    /// The model on an instance of this thread's (reused where one is
    /// free), minimising.
    #[allow(unsafe_code)]
    pub(crate) fn pass(self) -> Result<highs::Model> {
        let mut model = instance()?;
        let rowwise = 2;
        let minimise = 1;
        // SAFETY: a live instance; one cost and bound pair per column, one
        // bound pair and start per row, `index` and `value` of one length
        // with columns of this model.
        let status = unsafe {
            highs_sys::Highs_passLp(
                model.as_mut_ptr(),
                self.cost.len() as HighsInt,
                self.row_lower.len() as HighsInt,
                self.index.len() as HighsInt,
                rowwise,
                minimise,
                0.0,
                self.cost.as_ptr(),
                self.lower.as_ptr(),
                self.upper.as_ptr(),
                self.row_lower.as_ptr(),
                self.row_upper.as_ptr(),
                self.starts.as_ptr(),
                self.index.as_ptr(),
                self.value.as_ptr(),
            )
        };
        if status == highs_sys::STATUS_ERROR {
            keep(model);
            return Err(refused("the model"));
        }
        Ok(model)
    }
}

/// HiGHS refused a model, a row or a column.
pub(crate) fn refused(what: &str) -> Error {
    Error::SolverLimit(format!(
        "HiGHS rejects the LP as built ({what}): its coefficients are beyond its range \
         (nearly coincident or collinear vertices?)"
    ))
}

/// Instances kept per thread for the next models.
const KEPT: usize = 4;

thread_local! {
    static FREE: std::cell::RefCell<Vec<highs::Model>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A free instance of this thread's, emptied and back at HiGHS' default
/// options (quiet), else a new one.
#[allow(unsafe_code)]
fn instance() -> Result<highs::Model> {
    if let Some(mut model) = FREE.with_borrow_mut(|f| f.pop()) {
        // SAFETY: a live instance, kept by this thread only.
        unsafe {
            highs_sys::Highs_clearModel(model.as_mut_ptr());
            highs_sys::Highs_resetOptions(model.as_mut_ptr());
        }
        model.make_quiet();
        return Ok(model);
    }
    highs::Model::try_new(highs::RowProblem::default()).map_err(|_| refused("an empty model"))
}

/// Keeps a finished model's instance for the next model on this thread;
/// the instance back where this thread keeps enough (to be destroyed).
pub(crate) fn keep(model: highs::Model) -> Option<highs::Model> {
    FREE.with_borrow_mut(|f| {
        if f.len() < KEPT {
            f.push(model);
            None
        } else {
            Some(model)
        }
    })
}

/// This thread's kept instances (to be destroyed).
pub(crate) fn kept() -> Vec<highs::Model> {
    FREE.with_borrow_mut(std::mem::take)
}

/// Sets a column's bounds.
#[allow(unsafe_code)]
pub(crate) fn column_bounds(model: &mut highs::Model, c: Col, (lower, upper): (f64, f64)) {
    // SAFETY: a live instance and one of its columns.
    unsafe { highs_sys::Highs_changeColBounds(model.as_mut_ptr(), c.0 as HighsInt, lower, upper) };
}

/// A new column without entries.
#[allow(unsafe_code)]
pub(crate) fn add_column(
    model: &mut highs::Model,
    cost: f64,
    (lower, upper): (f64, f64),
) -> Result<Col> {
    let at = model.num_cols();
    // SAFETY: a live instance; no entries, so no arrays.
    let status = unsafe {
        highs_sys::Highs_addCol(
            model.as_mut_ptr(),
            cost,
            lower,
            upper,
            0,
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    if status == highs_sys::STATUS_ERROR {
        return Err(refused("a column added"));
    }
    Ok(Col(at))
}

/// A new row over existing columns.
#[allow(unsafe_code)]
pub(crate) fn add_row(
    model: &mut highs::Model,
    (lower, upper): (f64, f64),
    terms: &[(Col, f64)],
) -> Result<()> {
    let index: Vec<HighsInt> = terms.iter().map(|t| t.0 .0 as HighsInt).collect();
    let value: Vec<f64> = terms.iter().map(|t| t.1).collect();
    // SAFETY: a live instance; `index` and `value` of one length, columns
    // of this model.
    let status = unsafe {
        highs_sys::Highs_addRow(
            model.as_mut_ptr(),
            lower,
            upper,
            index.len() as HighsInt,
            index.as_ptr(),
            value.as_ptr(),
        )
    };
    if status == highs_sys::STATUS_ERROR {
        return Err(refused("a row added"));
    }
    Ok(())
}
