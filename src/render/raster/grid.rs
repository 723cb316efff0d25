//! The dot grid: which dot centres a range of positions covers, without libm calls (these
//! run per row in every pass).

/// `ceil(v)` for the dot grid, clamped at 0 (no libm call: this runs per row).
#[inline]
pub(super) fn ceil_nonneg(v: f32) -> usize {
    if v.is_nan() || v <= 0.0 {
        return 0;
    }
    // The cast saturates for huge values and infinity: do not step past it.
    let t = v as usize;
    if (t as f32) < v {
        t.saturating_add(1)
    } else {
        t
    }
}

/// `floor(v) + 1` clamped to `0..=limit`: the end of a range of dots (no libm call).
#[inline]
pub(super) fn floor_end(v: f32, limit: usize) -> usize {
    if v.is_nan() {
        return 0;
    }
    // Saturating: the cast saturates at infinities, and one more step must not overflow.
    let t = v as i64;
    let floor = if (t as f32) > v {
        t.saturating_sub(1)
    } else {
        t
    };
    floor
        .saturating_add(1)
        .clamp(0, limit.min(i64::MAX as usize) as i64) as usize
}
