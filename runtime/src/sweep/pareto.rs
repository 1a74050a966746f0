//! Stage `pareto` of `sweep`: which points no other point beats on both cost and error.

/// For each (cost, error), whether it is on the Pareto front: no other point is at most as
/// costly and at most as wrong, and strictly better in one. Points without a cost or error
/// (not measured) are never on it.
pub fn front(points: &[(Option<f64>, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            let Some(c) = c.filter(|c| c.is_finite()) else { return false };
            if !e.is_finite() {
                return false;
            }
            !points.iter().any(|&(oc, oe)| match oc {
                Some(oc) if oc.is_finite() && oe.is_finite() => oc <= c && oe <= e && (oc < c || oe < e),
                _ => false,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dominated_points_are_off_the_front() {
        let p = [
            (Some(1.0), 5.0),
            (Some(2.0), 3.0),
            (Some(3.0), 4.0),
            (Some(4.0), 1.0),
            (Some(2.0), 3.0),
            (None, 0.0),
        ];
        assert_eq!(front(&p), [true, true, false, true, true, false]);
        assert_eq!(front(&[(Some(1.0), f64::NAN)]), [false]);
    }
}
