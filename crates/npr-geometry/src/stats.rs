//! Order statistics for tests and benchmarks: one median and one percentile for the
//! whole workspace (NaN-tolerant, total order, no panics on empty input).

/// The `q`-quantile (`q` in [0, 1]) by the nearest-rank-below rule: the value at sorted
/// index `⌊q·n⌋` (clamped to the last), so `quantile(v, 0.5)` is the upper median.
/// NaN for no values. Sorting uses `f64::total_cmp`.
pub fn quantile(values: impl IntoIterator<Item = f64>, q: f64) -> f64 {
    let mut v: Vec<f64> = values.into_iter().collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let i = ((v.len() as f64 * q.clamp(0.0, 1.0)) as usize).min(v.len() - 1);
    v[i]
}

/// The median (upper median for an even count: sorted index `n / 2`); NaN for no values.
pub fn median(values: impl IntoIterator<Item = f64>) -> f64 {
    quantile(values, 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_and_quantiles() {
        assert!(median(std::iter::empty()).is_nan());
        assert_eq!(median([3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0, 3.0, 2.0]), 3.0);
        let v: Vec<f64> = (0..100).map(f64::from).collect();
        assert_eq!(quantile(v.iter().copied(), 0.95), 95.0);
        assert_eq!(quantile(v.iter().copied(), 1.0), 99.0);
        assert_eq!(quantile(v, 0.0), 0.0);
    }
}
