//! Axis ticks: round steps (1, 2 or 5 × 10^k), ranges widened to whole steps, and tick labels
//! with just the decimals the step needs.

/// Tick spacing of the form 1, 2 or 5 × 10^k giving at most about `target` intervals over
/// [lo, hi], and the ticks (multiples of it) inside the interval.
pub fn nice_ticks(lo: f64, hi: f64, target: usize) -> (f64, Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (1.0, vec![]);
    }
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
    let span = hi - lo;
    if !span.is_finite() || span <= 0.0 {
        return (1.0, vec![lo]);
    }
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|&s| span / s <= target.max(1) as f64 * (1.0 + 1e-9))
        .unwrap_or(10.0 * mag);
    let (k0, k1) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
    let ticks = (0..=((k1 - k0) as i64).clamp(-1, 1000))
        .map(|i| {
            let v = (k0 + i as f64) * step;
            if v.abs() < step * 1e-9 {
                0.0
            } else {
                v
            }
        })
        .collect();
    (step, ticks)
}

/// The data interval [lo, hi] widened outwards to whole tick steps (and to a unit interval when
/// it is empty), for automatic axis ranges.
pub fn nice_range(lo: f64, hi: f64, target: usize) -> (f64, f64) {
    let (lo, hi) = match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (lo.min(hi), lo.max(hi)),
        _ => return (0.0, 1.0),
    };
    let (lo, hi) = if hi - lo <= 1e-12 * lo.abs().max(1e-300) {
        let pad = if lo == 0.0 { 1.0 } else { lo.abs() * 0.5 };
        (lo - pad, hi + pad)
    } else {
        (lo, hi)
    };
    let (step, _) = nice_ticks(lo, hi, target);
    (
        (lo / step + 1e-9).floor() * step,
        (hi / step - 1e-9).ceil() * step,
    )
}

/// A tick label with as many decimals as the step needs.
pub fn format_tick(v: f64, step: f64) -> String {
    let a = step.abs();
    if a >= 1e6 || (a > 0.0 && a < 1e-4) {
        return format!("{v:e}");
    }
    let decimals = (-(a.log10() + 1e-9).floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    #[test]
    fn nice_ticks_pick_round_steps() {
        let (s, t) = nice_ticks(360.0, 830.0, 5);
        assert_eq!(s, 100.0);
        assert!(close(&t, &[400.0, 500.0, 600.0, 700.0, 800.0]), "{t:?}");
        let (s, t) = nice_ticks(360.0, 830.0, 10);
        assert_eq!(s, 50.0);
        assert_eq!(t.first(), Some(&400.0));
        let (s, t) = nice_ticks(0.0, 1.0, 5);
        assert_eq!(s, 0.2);
        assert!(close(&t, &[0.0, 0.2, 0.4, 0.6, 0.8, 1.0]), "{t:?}");
        let (s, t) = nice_ticks(-90.0, 90.0, 6);
        assert_eq!(s, 50.0);
        assert!(close(&t, &[-50.0, 0.0, 50.0]), "{t:?}");
        let (s, _) = nice_ticks(0.0, 0.0032, 4);
        assert!((s - 0.001).abs() < 1e-15);
        assert_eq!(nice_ticks(5.0, 5.0, 5).1, vec![5.0]);
        assert!(nice_ticks(f64::NAN, 1.0, 5).1.is_empty());
        assert_eq!(nice_ticks(1.0, 0.0, 5).1.len(), 6, "reversed ranges work");
    }

    #[test]
    fn ranges_and_labels_are_tidy() {
        assert_eq!(nice_range(0.03, 0.97, 5), (0.0, 1.0));
        assert_eq!(nice_range(380.0, 780.0, 8), (350.0, 800.0));
        assert_eq!(nice_range(2.0, 2.0, 5), (1.0, 3.0));
        assert_eq!(nice_range(f64::INFINITY, -f64::INFINITY, 5), (0.0, 1.0));
        assert_eq!(format_tick(0.6000000001, 0.2), "0.6");
        assert_eq!(format_tick(-1e-17, 0.2), "0.0");
        assert_eq!(format_tick(500.0, 50.0), "500");
        assert_eq!(format_tick(0.025, 0.005), "0.025");
    }
}
