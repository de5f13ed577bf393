//! The perceptual colormap (viridis) and the value range it spans: automatic (min/max of what
//! is on screen) or fixed by the user; for differences, a diverging map (blue below zero, red
//! above) on a range symmetric about zero.

/// How the colour range is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Range {
    /// Min and max of the values on screen.
    Auto,
    /// A range the user set, in display units.
    Fixed {
        /// Value mapped to the first colour.
        min: f64,
        /// Value mapped to the last colour.
        max: f64,
    },
}

/// The range actually used for a set of values (display units); never empty.
pub fn resolve(range: Range, values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = match range {
        Range::Auto => values
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            }),
        Range::Fixed { min, max } => (min, max),
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    if hi - lo <= 1e-12 * (lo.abs() + hi.abs()).max(1e-30) {
        return (lo, lo + 1e-12_f64.max(lo.abs() * 1e-6));
    }
    (lo, hi)
}

/// Colour of `value` in [lo, hi] (clamped), as sRGB in [0, 1].
pub fn color(value: f64, lo: f64, hi: f64) -> [f32; 3] {
    let t = ((value - lo) / (hi - lo)).clamp(0.0, 1.0);
    let c = colorous::VIRIDIS.eval_continuous(if t.is_finite() { t } else { 0.0 });
    [
        f32::from(c.r) / 255.0,
        f32::from(c.g) / 255.0,
        f32::from(c.b) / 255.0,
    ]
}

/// The range of a difference field: automatic is ±(largest |value|), so zero sits in the
/// middle; never empty.
pub fn resolve_symmetric(range: Range, values: impl Iterator<Item = f64>) -> (f64, f64) {
    match range {
        Range::Auto => {
            let m = values
                .filter(|v| v.is_finite())
                .fold(0.0, |m: f64, v| m.max(v.abs()));
            let m = if m > 0.0 { m } else { 1e-12 };
            (-m, m)
        }
        fixed => resolve(fixed, std::iter::empty()),
    }
}

/// Colour of a difference `value` in [lo, hi] (clamped) on the diverging blue–white–red map,
/// as sRGB in [0, 1].
pub fn diverging(value: f64, lo: f64, hi: f64) -> [f32; 3] {
    let t = ((value - lo) / (hi - lo)).clamp(0.0, 1.0);
    // RdBu runs red to blue: reversed, so negative is blue
    let c = colorous::RED_BLUE.eval_continuous(1.0 - if t.is_finite() { t } else { 0.5 });
    [
        f32::from(c.r) / 255.0,
        f32::from(c.g) / 255.0,
        f32::from(c.b) / 255.0,
    ]
}

/// The grey of surfaces that carry no value (bodies around an interface field).
pub const NEUTRAL: [f32; 3] = [0.72, 0.72, 0.74];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_of_the_range_map_to_the_ends_of_viridis() {
        let dark = color(0.0, 0.0, 1.0);
        let bright = color(1.0, 0.0, 1.0);
        // viridis runs from dark purple (#440154) to yellow (#fde725)
        assert!((dark[0] - 0x44 as f32 / 255.0).abs() < 0.01 && dark[2] > dark[1]);
        assert!((bright[0] - 0xfd as f32 / 255.0).abs() < 0.01 && bright[1] > bright[2]);
        assert_eq!(color(-5.0, 0.0, 1.0), dark);
        assert_eq!(color(7.0, 0.0, 1.0), bright);
    }

    #[test]
    fn auto_range_spans_the_values_and_never_collapses() {
        assert_eq!(
            resolve(Range::Auto, [3.0, -1.0, 2.0].into_iter()),
            (-1.0, 3.0)
        );
        let (lo, hi) = resolve(Range::Auto, [2.0, 2.0].into_iter());
        assert!(lo == 2.0 && hi > lo);
        assert_eq!(resolve(Range::Auto, std::iter::empty()), (0.0, 1.0));
        let fixed = Range::Fixed { min: 0.0, max: 5.0 };
        assert_eq!(resolve(fixed, [100.0].into_iter()), (0.0, 5.0));
    }

    #[test]
    fn a_difference_range_is_symmetric_and_zero_is_the_middle_colour() {
        assert_eq!(
            resolve_symmetric(Range::Auto, [-1.0, 3.0].into_iter()),
            (-3.0, 3.0)
        );
        let (lo, hi) = resolve_symmetric(Range::Auto, [0.0, 0.0].into_iter());
        assert!(lo < 0.0 && hi > 0.0 && lo == -hi);
        let white = diverging(0.0, -1.0, 1.0);
        assert!(white.iter().all(|&c| c > 0.9), "{white:?}");
        let (blue, red) = (diverging(-1.0, -1.0, 1.0), diverging(1.0, -1.0, 1.0));
        assert!(blue[2] > blue[0] && red[0] > red[2], "{blue:?} {red:?}");
    }
}
