//! What the GPU benches share: how much to measure (the full bench, or the tests' smoke run
//! of it) and the median and quartiles their figures are.

/// How much to measure: the full bench, or one small round of everything (the tests' run).
#[derive(Clone, Copy, PartialEq)]
pub enum Size {
    Full,
    Smoke,
}

impl Size {
    /// `full` for the bench, `smoke` for its run in the tests.
    pub fn pick<T>(self, full: T, smoke: T) -> T {
        if self == Size::Full {
            full
        } else {
            smoke
        }
    }
}

/// Median and quartiles of a list.
pub fn quartiles(mut v: Vec<f64>) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (at(0.25), at(0.5), at(0.75))
}
