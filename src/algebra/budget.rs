//! A work meter for symbolic arithmetic: how a command bounds a computation whose cost the
//! input cannot predict (gcds of rational functions in the plant's parameters).
//!
//! A command opens a [`Meter`] with a budget of coefficient products; the gcds and products of
//! [`super::Fraction`] charge it. When it runs out, the arithmetic stops doing real work (gcds
//! answer 1, so every later step is cheap) and the command, which asks [`Meter::exhausted`]
//! before it reads any result, refuses with the limit named. A value computed after the meter
//! ran out is never shown. Outside a meter nothing is charged and nothing stops.

use std::cell::Cell;

thread_local! {
    static LEFT: Cell<Option<u64>> = const { Cell::new(None) };
    static OUT: Cell<bool> = const { Cell::new(false) };
}

/// Charges `work` coefficient products to the open meter, if any.
pub fn charge(work: u64) {
    LEFT.with(|left| {
        if let Some(l) = left.get() {
            if work > l {
                left.set(Some(0));
                OUT.with(|o| o.set(true));
            } else {
                left.set(Some(l - work));
            }
        }
    });
}

/// Whether a meter is open on this thread.
pub fn is_open() -> bool {
    LEFT.with(Cell::get).is_some()
}

/// The work left on the open meter (`None` without one).
pub fn left() -> Option<u64> {
    LEFT.with(Cell::get)
}

/// Whether the open meter has run out.
pub fn exhausted() -> bool {
    OUT.with(Cell::get)
}

/// An open work budget; closed (and reset) when dropped.
#[derive(Debug)]
pub struct Meter {
    budget: u64,
    outer: Option<u64>,
    outer_out: bool,
}

impl Meter {
    /// Opens a meter of `budget` coefficient products on this thread.
    pub fn open(budget: u64) -> Self {
        let outer = LEFT.with(|l| l.replace(Some(budget)));
        let outer_out = OUT.with(|o| o.replace(false));
        Meter {
            budget,
            outer,
            outer_out,
        }
    }
    /// The budget it was opened with.
    pub fn budget(&self) -> u64 {
        self.budget
    }
    /// Whether the budget has run out (results computed since are meaningless).
    pub fn exhausted(&self) -> bool {
        exhausted()
    }
}

impl Drop for Meter {
    fn drop(&mut self) {
        LEFT.with(|l| l.set(self.outer));
        OUT.with(|o| o.set(self.outer_out));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_meter_runs_out_and_closes() {
        assert!(!exhausted());
        charge(u64::MAX); // no meter: nothing happens
        assert!(!exhausted());
        {
            let m = Meter::open(10);
            charge(6);
            assert!(!m.exhausted());
            charge(6);
            assert!(m.exhausted());
        }
        assert!(!exhausted());
    }
}
