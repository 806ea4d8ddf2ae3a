//! The head-shield layout of the `scales` texture (`layout="head"`): the large plates on a
//! snake's head as the Voronoi cells of a fixed, left–right symmetric set of seed points laid
//! out on a map of the head.
//!
//! The map is the UV of the `snake` shape's `head` part: v from the snout tip (0) to the back of
//! the head (1), u around the head from one lip (0) over the crown (0.5) to the other (1). The
//! seeds follow the shields of a colubroid head as drawn in field guides (the names below; the
//! sunbeam snake's are close to this set, with large parietals), placed by eye: rostral at the tip, paired
//! internasals and prefrontals, a single frontal between the supraoculars, large parietals, the
//! nasal, loreal, pre- and postocular and temporal shields on the sides, and eight supra- and
//! eight infralabials along each side of the mouth. A ring of seeds just outside the map (behind the head and beyond each lip)
//! closes the outer shields with a groove at the map's edge, where the body's dorsal rows and
//! the belly part begin. In cell space the map is `HEAD_CELLS` units across, so a shield is
//! about one unit wide like a lattice scale and `gap`, `dome` and `tilt_degrees` mean the same.
//!
//! Limits: one fixed layout (no per-species variants); the shields' outlines are straight
//! Voronoi edges, rounded at the corners only by the groove.

use crate::math::Vec2;

/// Cell-space units across the head map (a shield is about one unit wide).
pub(crate) const HEAD_CELLS: f32 = 8.0;

/// Where the eye sits on the map: its offset from the midline and its v (the `snake` shape
/// puts its eyes here, between the pre- and postocular shields).
pub(crate) const EYE_OFFSET: f32 = 0.22;
pub(crate) const EYE_V: f32 = 0.47;

/// Seeds on one side of the crown's midline, as (offset from u = 0.5, v); those at offset 0
/// lie on the midline and appear once.
const HALF_SEEDS: &[(f32, f32)] = &[
    (0.0, 0.03),  // rostral
    (0.06, 0.16), // internasal
    (0.17, 0.13), // nasal
    (0.07, 0.33), // prefrontal
    (0.18, 0.31), // loreal
    (0.21, 0.40), // preocular
    (0.0, 0.55),  // frontal
    (0.12, 0.51), // supraocular
    (0.23, 0.57), // postocular
    (0.08, 0.83), // parietal
    (0.21, 0.77), // anterior temporal
    (0.18, 0.95), // posterior temporal
];

/// Seeds just outside the map, closing its edge: (offset, v).
const BORDER_SEEDS: &[(f32, f32)] = &[
    (0.0, 1.16),
    (0.12, 1.16),
    (0.24, 1.16),
    (0.36, 1.16),
    (0.48, 1.16),
];

/// Number of supra- and infralabials per side and their rows' offsets from the midline (the
/// mouth runs between them).
const LABIALS: usize = 8;
const SUPRALABIAL_OFFSET: f32 = 0.295;
const INFRALABIAL_OFFSET: f32 = 0.405;
/// Offset of the seeds beyond the lower lip (their bisector with the infralabials is the map's
/// edge, where the belly part begins).
const BEYOND_LIP: f32 = 1.0 - INFRALABIAL_OFFSET;

/// All seeds in map coordinates (u, v); the first `shields()` are the head's own shields.
pub fn seeds() -> Vec<Vec2> {
    let mut out = Vec::new();
    let mut both = |du: f32, v: f32| {
        out.push(Vec2::new(0.5 - du, v));
        if du > 0.0 {
            out.push(Vec2::new(0.5 + du, v));
        }
    };
    for &(du, v) in HALF_SEEDS {
        both(du, v);
    }
    for k in 0..LABIALS {
        both(SUPRALABIAL_OFFSET, (k as f32 + 0.6) / LABIALS as f32);
        both(INFRALABIAL_OFFSET, (k as f32 + 0.3) / LABIALS as f32);
    }
    for &(du, v) in BORDER_SEEDS {
        both(du, v);
    }
    // Mirror images of the infralabials across the map's edge u = 0 (and 1).
    for k in 0..LABIALS {
        both(BEYOND_LIP, (k as f32 + 0.3) / LABIALS as f32);
    }
    out
}

#[cfg(test)]
/// How many of [`seeds`] are shields on the head (the rest only close the edges).
pub(crate) fn shields() -> usize {
    let per_side = |list: &[(f32, f32)]| -> usize {
        list.iter()
            .map(|&(du, _)| if du > 0.0 { 2 } else { 1 })
            .sum()
    };
    per_side(HALF_SEEDS) + 4 * LABIALS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_symmetric_and_inside_the_map() {
        let s = seeds();
        let n = shields();
        for (i, p) in s.iter().enumerate() {
            let mirror = Vec2::new(1.0 - p.x, p.y);
            assert!(
                s.iter().any(|q| (*q - mirror).length() < 1e-6),
                "{p} unpaired"
            );
            let inside = (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y);
            assert_eq!(inside, i < n, "seed {i} at {p}");
        }
        // No two seeds coincide (each would leave a zero-size shield).
        for (i, a) in s.iter().enumerate() {
            for b in &s[i + 1..] {
                assert!((*a - *b).length() > 0.04, "{a} and {b}");
            }
        }
    }
}
