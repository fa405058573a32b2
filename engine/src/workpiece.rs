//! What is clamped on the machine's table — the stock, a fixture, a tool setter — as boxes the
//! probe can touch: the skip signal of G31 (`interp::skip`) comes from them. Without boxes
//! nothing is there to touch and a G31 runs its whole move, as a probe moving through air does.
//!
//! The boxes are fixed in the table frame: the frame that turns with the rotary table
//! (machine coordinates on a machine without table axes), in which `fivex kin fk`, the trace's
//! `tip_table` and a work offset give points; a point of the workpiece system is in the table
//! frame at `point + work offset + spindle nose` (`docs/conventions.md`, "Workpiece and
//! probing"). Pure geometry, no IO.

use crate::kin::Vec3;
use serde::{Deserialize, Serialize};

/// The most boxes one workpiece may have: a setup, not a mesh.
pub const MAX_BOXES: usize = 256;

/// A ball this near a box touches it (mm): the search's minimum of the distance lands beside a
/// flat bottom (a path through a box) by rounding, and a path that grazes a box within a
/// nanometre touches it.
const TOUCH: f64 = 1e-9;

/// Bisection steps of the contact search: the fraction of the move is exact to 2⁻⁶⁰ of its
/// length (a 10 m move to 1e-14 mm), below any coordinate's rounding.
const STEPS: usize = 60;

/// Everything on the table.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Workpiece {
    /// Axis-aligned boxes in the table frame, mm.
    #[serde(default)]
    pub boxes: Vec<Cuboid>,
}

/// One box: its least and greatest corner in the table frame, mm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct Cuboid {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Cuboid {
    /// Distance from `p` to the box (0 inside or on it).
    fn distance(&self, p: Vec3) -> f64 {
        let d: [f64; 3] = std::array::from_fn(|k| (self.min[k] - p[k]).max(p[k] - self.max[k]).max(0.0));
        Vec3::from(d).norm()
    }

    /// The first fraction of the segment `a → b` at which a ball of radius `r` centred on it
    /// touches the box. The distance from a point moving on a line to a convex set is a convex
    /// function of the fraction, so its least value is found by a golden-section search and
    /// the first touch by bisection before it, where the distance only falls.
    fn first_contact(&self, a: Vec3, b: Vec3, r: f64) -> Option<f64> {
        let at = |t: f64| self.distance(a + (b - a) * t);
        if at(0.0) <= r + TOUCH {
            return Some(0.0);
        }
        let golden = (5f64.sqrt() - 1.0) / 2.0;
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..2 * STEPS {
            let (m1, m2) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
            if at(m1) <= at(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let least = if at(1.0) <= at(lo) { 1.0 } else { lo };
        if at(least) > r + TOUCH {
            return None;
        }
        let (mut out, mut touching) = (0.0, least);
        for _ in 0..STEPS {
            let mid = (out + touching) / 2.0;
            if at(mid) <= r {
                touching = mid;
            } else {
                out = mid;
            }
        }
        Some(touching)
    }
}

impl Workpiece {
    /// Whether anything is on the table.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// The reason the workpiece cannot be used, if any: a corner not finite, a box whose least
    /// corner is not below its greatest on every axis, more than [`MAX_BOXES`] boxes.
    pub fn check(&self) -> Result<(), String> {
        if self.boxes.len() > MAX_BOXES {
            return Err(format!("{} boxes: at most {MAX_BOXES}", self.boxes.len()));
        }
        for (i, b) in self.boxes.iter().enumerate() {
            if b.min.iter().chain(&b.max).any(|v| !v.is_finite()) {
                return Err(format!("box {i}: every corner coordinate must be a finite number"));
            }
            if (0..3).any(|k| b.min[k] >= b.max[k]) {
                return Err(format!("box {i}: min must be less than max on every axis"));
            }
        }
        Ok(())
    }

    /// The first fraction (0–1) of the straight move of a ball of radius `radius` whose centre
    /// goes from `a` to `b` (table frame) at which it touches any box; `None` if it touches
    /// none. A ball touching a box where it starts touches at 0.
    pub fn first_contact(&self, a: Vec3, b: Vec3, radius: f64) -> Option<f64> {
        self.boxes.iter().filter_map(|c| c.first_contact(a, b, radius)).min_by(f64::total_cmp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block() -> Workpiece {
        Workpiece { boxes: vec![Cuboid { min: [0.0, 0.0, -20.0], max: [50.0, 40.0, 0.0] }] }
    }

    #[test]
    fn a_ball_coming_down_touches_the_top_at_its_radius() {
        let t = block().first_contact(Vec3::new(10.0, 10.0, 13.0), Vec3::new(10.0, 10.0, -7.0), 3.0).unwrap();
        // The centre reaches z = 3 after 10 of 20 mm.
        assert!((t - 0.5).abs() < 1e-15, "{t}");
    }

    #[test]
    fn a_ball_beside_the_box_passes_it_and_one_grazing_an_edge_touches_it_there() {
        let w = block();
        assert_eq!(w.first_contact(Vec3::new(-3.5, 10.0, 5.0), Vec3::new(-3.5, 10.0, -30.0), 3.0), None);
        // Coming down beside the edge x = 0, z = 0 at 2 mm out: the ball of radius 3 touches the
        // edge when its centre is √(3² − 2²) above z = 0.
        let t = w.first_contact(Vec3::new(-2.0, 10.0, 10.0), Vec3::new(-2.0, 10.0, -10.0), 3.0).unwrap();
        let z = 10.0 - 20.0 * t;
        assert!((z - 5f64.sqrt()).abs() < 1e-12, "{z}");
    }

    #[test]
    fn the_first_of_two_boxes_is_the_nearer_on_the_way() {
        let mut w = block();
        w.boxes.push(Cuboid { min: [60.0, 0.0, -20.0], max: [70.0, 40.0, 0.0] });
        // Moving in −X at z = −5 from x = 100: the second box's face x = 70 comes first.
        let t = w.first_contact(Vec3::new(100.0, 10.0, -5.0), Vec3::new(-50.0, 10.0, -5.0), 0.0).unwrap();
        assert!((100.0 - 150.0 * t - 70.0).abs() < 1e-12);
    }

    #[test]
    fn a_ball_already_touching_touches_at_once_and_a_move_that_stops_short_touches_nothing() {
        let w = block();
        assert_eq!(w.first_contact(Vec3::new(10.0, 10.0, 2.0), Vec3::new(10.0, 10.0, 30.0), 3.0), Some(0.0));
        assert_eq!(w.first_contact(Vec3::new(10.0, 10.0, 30.0), Vec3::new(10.0, 10.0, 3.5), 3.0), None);
    }

    #[test]
    fn check_refuses_what_no_box_can_be() {
        let mut w = block();
        assert!(w.check().is_ok());
        w.boxes[0].max[2] = -20.0;
        assert!(w.check().unwrap_err().contains("min must be less than max"));
        w.boxes[0].max[2] = f64::NAN;
        assert!(w.check().unwrap_err().contains("finite"));
    }

    proptest::proptest! {
        /// Where the search says the ball touches, it is at its radius from the box, and at no
        /// earlier sampled point nearer than that.
        #[test]
        fn the_contact_is_the_first_point_at_the_radius(
            a in proptest::array::uniform3(-80.0f64..120.0),
            b in proptest::array::uniform3(-80.0f64..120.0),
            r in 0.0f64..6.0,
        ) {
            let w = block();
            let (a, b) = (Vec3::from(a), Vec3::from(b));
            let d = |t: f64| w.boxes[0].distance(a + (b - a) * t);
            match w.first_contact(a, b, r) {
                Some(t) if t > 0.0 => {
                    proptest::prop_assert!((d(t) - r).abs() < 1e-9, "distance {} at {t}", d(t));
                    for k in 0..1000 {
                        let s = t * k as f64 / 1000.0;
                        proptest::prop_assert!(d(s) >= r - 1e-9, "nearer at {s} than at the contact {t}");
                    }
                }
                Some(_) => proptest::prop_assert!(d(0.0) <= r),
                None => {
                    for k in 0..=1000 {
                        let s = k as f64 / 1000.0;
                        proptest::prop_assert!(d(s) > r - 1e-9, "touches at {s}, none found");
                    }
                }
            }
        }
    }
}
