//! Ticks for a logarithmic axis: a tick at every decade, labelled cleanly
//! (`0.001`, `0.01`, `0.1`, `1`, `10`, ... or `1e-5`, `1e6` beyond), with
//! unlabelled minor ticks at 2..9 times each decade. Labels are built from
//! integers, never by printing a float, so `0.30000000000000004` cannot
//! appear; no label repeats; at most `max_labels` labels are given (every
//! second or third decade when the range is wide), so they do not overlap.
//! On a range narrower than a decade the minor ticks 2 and 5 (or all) are
//! labelled so the axis still reads.

/// One tick: where, and its label when it has one.
#[derive(Debug, Clone, PartialEq)]
pub struct Tick {
    pub value: f64,
    pub label: Option<String>,
}

/// `m * 10^k` written plainly for -2 <= k <= 4 (`0.05`, `300`), else as
/// `{m}e{k}` (`1e-3`, `5e6`).
pub fn label(m: u32, k: i32) -> String {
    debug_assert!((1..10).contains(&m));
    if (-2..=4).contains(&k) {
        if k >= 0 {
            format!("{m}{}", "0".repeat(k as usize))
        } else {
            format!("0.{}{m}", "0".repeat((-k - 1) as usize))
        }
    } else {
        format!("{m}e{k}")
    }
}

fn value(m: u32, k: i32) -> f64 {
    // parsed from the exact decimal, so 3e-1 is the f64 nearest 0.3
    format!("{m}e{k}").parse().expect("a decimal")
}

/// The ticks of a log axis over [lo, hi] (positive, finite, lo < hi), with
/// at most `max_labels` (>= 2) labels. Empty for a range that is not one.
pub fn log_ticks(lo: f64, hi: f64, max_labels: usize) -> Vec<Tick> {
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi > lo) {
        return Vec::new();
    }
    let max_labels = max_labels.max(2);
    let (k_lo, k_hi) = (lo.log10().floor() as i32 - 1, hi.log10().ceil() as i32 + 1);
    let inside = |v: f64| v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12);
    let mut all: Vec<(u32, i32, f64)> = Vec::new();
    for k in k_lo..=k_hi {
        for m in 1..10 {
            let v = value(m, k);
            if inside(v) {
                all.push((m, k, v));
            }
        }
    }
    let decades: Vec<i32> = all.iter().filter(|t| t.0 == 1).map(|t| t.1).collect();
    // which ticks carry a label
    let labelled: Box<dyn Fn(u32, i32) -> bool> = if decades.len() >= 2 {
        // the smallest stride that fits, on decades divisible by it (1e-6,
        // 1, 1e6) when that leaves two labels, else counted from the first
        let count = |stride: i32, base: i32| {
            decades
                .iter()
                .filter(|k| (*k - base).rem_euclid(stride) == 0)
                .count()
        };
        let first = decades[0];
        let stride = (1..)
            .find(|s| count(*s, first) <= max_labels)
            .expect("a stride as wide as the range fits");
        let base = if count(stride, 0) >= 2 && count(stride, 0) <= max_labels {
            0
        } else {
            first
        };
        Box::new(move |m, k| m == 1 && (k - base).rem_euclid(stride) == 0)
    } else {
        // under about a decade: label the 1s, 2s and 5s, or every tick
        let few = |set: &[u32]| all.iter().filter(|t| set.contains(&t.0)).count();
        let set: Vec<u32> = if few(&[1, 2, 5]) >= 2 && few(&[1, 2, 5]) <= max_labels {
            vec![1, 2, 5]
        } else if all.len() <= max_labels {
            (1..10).collect()
        } else {
            vec![1, 5]
        };
        Box::new(move |m, _| set.contains(&m))
    };
    all.iter()
        .map(|&(m, k, v)| Tick {
            value: v,
            label: labelled(m, k).then(|| label(m, k)),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(t: &[Tick]) -> Vec<&str> {
        t.iter().filter_map(|t| t.label.as_deref()).collect()
    }

    #[test]
    fn decades_are_labelled_cleanly() {
        let t = log_ticks(1e-3, 10.0, 10);
        assert_eq!(labels(&t), ["1e-3", "0.01", "0.1", "1", "10"]);
        assert_eq!(label(5, -3), "5e-3");
        // 2..9 minor ticks between, unlabelled
        let minors: Vec<f64> = t
            .iter()
            .filter(|t| t.label.is_none() && t.value < 1.0 && t.value > 0.1)
            .map(|t| t.value)
            .collect();
        assert_eq!(minors, [0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]);
        assert_eq!(label(3, -1), "0.3");
        assert_eq!(label(1, 6), "1e6");
        assert_eq!(label(1, -7), "1e-7");
        assert_eq!(label(1, 4), "10000");
    }

    #[test]
    fn no_float_noise_no_duplicates_and_ordered() {
        for (lo, hi) in [
            (0.05, 0.09),
            (0.03, 0.31),
            (1e-9, 1e9),
            (0.7, 1.3),
            (1e-300, 1e300),
            (0.1, 0.1000001),
            (2.5, 2500.0),
        ] {
            for max in [2, 5, 8, 20] {
                let t = log_ticks(lo, hi, max);
                let l = labels(&t);
                assert!(l.len() <= max, "{lo}..{hi} max {max}: {l:?}");
                let mut seen = std::collections::BTreeSet::new();
                for s in &l {
                    assert!(s.len() <= 6, "short label {s}");
                    assert!(!s.contains("000000"), "no float noise: {s}");
                    assert!(seen.insert(*s), "duplicate {s} in {l:?}");
                }
                assert!(t.windows(2).all(|w| w[0].value < w[1].value), "{t:?}");
                assert!(t
                    .iter()
                    .all(|t| t.value >= lo * 0.999 && t.value <= hi * 1.001));
            }
        }
    }

    #[test]
    fn the_issue_17_axis_reads() {
        // timeseries.svg's error axis from about 0.04 to 0.35
        let t = log_ticks(0.04, 0.35, 8);
        assert_eq!(labels(&t), ["0.05", "0.1", "0.2"]);
        assert!(t.iter().any(|t| t.value == 0.3 && t.label.is_none()));
        // a range below a decade with room labels every tick
        let t = log_ticks(0.05, 0.09, 8);
        assert_eq!(labels(&t), ["0.05", "0.06", "0.07", "0.08", "0.09"]);
        // wide ranges thin the decades
        let t = log_ticks(1e-12, 1e12, 5);
        assert_eq!(labels(&t), ["1e-10", "1e-5", "1", "1e5", "1e10"]);
        let t = log_ticks(1e-12, 1e12, 3);
        assert_eq!(labels(&t), ["1e-9", "1", "1e9"]);
    }

    #[test]
    fn bad_ranges_give_no_ticks() {
        for (lo, hi) in [
            (0.0, 1.0),
            (-1.0, 1.0),
            (1.0, 1.0),
            (2.0, 1.0),
            (f64::NAN, 1.0),
        ] {
            assert!(log_ticks(lo, hi, 5).is_empty());
        }
    }
}
