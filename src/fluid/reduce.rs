//! Largest values over whole fields, eight running maxima at a time so the loops vectorise
//! (a single running maximum is a chain of dependent instructions the compiler keeps scalar).
//! `max` is exact, so the order does not change the result.

/// Running maxima per loop.
const LANES: usize = 8;

/// The largest `key(v)` over `values`, 0 for none or if every key is below 0 (NaN keys are
/// skipped).
#[inline(always)]
fn largest(values: &[f32], key: impl Fn(f32) -> f32) -> f32 {
    let mut lanes = [0.0f32; LANES];
    let (chunks, rest) = values.as_chunks::<LANES>();
    // `if v > m` rather than `f32::max`: the same result (a NaN key compares false and is
    // skipped) in one instruction, where `max`'s NaN rule costs three.
    let keep = |m: f32, v: f32| if v > m { v } else { m };
    for chunk in chunks {
        for l in 0..LANES {
            lanes[l] = keep(lanes[l], key(chunk[l]));
        }
    }
    for (l, &v) in rest.iter().enumerate() {
        lanes[l] = keep(lanes[l], key(v));
    }
    lanes.into_iter().fold(0.0, keep)
}

/// The largest `|v|` over `values` (0 for none; NaN skipped).
pub(crate) fn max_abs(values: &[f32]) -> f32 {
    largest(values, f32::abs)
}

/// The largest value over `values`, at least 0 (NaN skipped).
pub(crate) fn max_non_negative(values: &[f32]) -> f32 {
    largest(values, |v| v)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_is_found_anywhere_and_nan_is_skipped() {
        let mut values: Vec<f32> = (0..37).map(|i| (i as f32 * 0.37).sin()).collect();
        for at in [0, 7, 8, 31, 36] {
            let mut v = values.clone();
            v[at] = -5.0;
            assert_eq!(max_abs(&v), 5.0, "at {at}");
            v[at] = 5.0;
            assert_eq!(max_non_negative(&v), 5.0, "at {at}");
        }
        values[3] = f32::NAN;
        assert!(max_abs(&values) <= 1.0);
        assert_eq!(max_abs(&[]), 0.0);
        assert_eq!(max_non_negative(&[-1.0, -2.0]), 0.0);
    }
}
