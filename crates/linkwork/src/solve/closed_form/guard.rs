//! A branch check from positions alone: where a sweep asks only for positions, a
//! closed-form step is accepted when no dyad can have met its singular configuration
//! between the two steps, shown from the lengths and the solved positions, without the
//! rates, accelerations and two-way check of the careful path (`stepping::branch`).
//!
//! Why it is sound. A dyad's branch can change only where it is singular: an RRR dyad's
//! where the distance D = |C - A| between its known pins reaches |r1 - r2| or r1 + r2 (the
//! triangle A B C flat), an RRP dyad's where the offset of A from the slide's line reaches
//! r1 (the circle tangent to the line). Off those, B on the branch of a sign is a
//! continuous function of the known pins, so the true motion keeps the sign. Let m be the
//! step's margin (D's distance to the nearer of the two limits, r1 - |offset|) at the
//! solved configuration at the end of the step, and L a bound on the path length of the
//! known pins over the step (`Travel`). D (the offset) moves by at most L, so with L < m
//! the margin stays at least m - L > 0 over the whole step: no singular configuration
//! was met, and the closed form's branch is the motion's. The bound asked is L <= m / 2
//! (`GUARD`), which leaves m / 2 for round-off and keeps the bodies' turn bounded below.
//!
//! The path lengths come from the inputs: a crank on the ground whose law is constant or
//! linear turns by |rate h| (other laws: no bound, the careful path). A dyad body's turn
//! over the step is the integral of its angular rate, which its 2 x 2 rate system bounds
//! by the known pins' speeds over |sin| of the angle at B (RRR: |w1| <= |vC - vA| /
//! (r1 sin), from |det| = r1 r2 sin) or over the height of B along the line (RRP: |w| <=
//! |vA| / h): with the margin at least m - L, Heron's formula (RRR) or h^2 = r1^2 -
//! offset^2 (RRP) bounds sin and h below, so the turn is at most L over that. A pin's path
//! on a body is at most the path of the body's reference point plus its distance from it
//! times the body's turn. Each bound is formed from the bodies before it in the plan's
//! order, so a chain of dyads (Jansen's leg) is bounded dyad by dyad.

use crate::constraints::sub;
use crate::input::motion::MotionLaw;

/// The known pins' path over a step may be at most this fraction of the dyad's margin.
pub const GUARD: f64 = 0.5;

/// A bound on a body's motion over one step: its reference point (at the step's end), a
/// bound on that point's path length, and a bound on the body's turn (radians).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Travel {
    pub r: [f64; 2],
    pub len: f64,
    pub turn: f64,
}

impl Travel {
    /// A bound on the path of the body's point now at `p`.
    #[inline(always)]
    pub fn pin(&self, p: [f64; 2]) -> f64 {
        let d = sub(p, self.r);
        self.len + (d[0] * d[0] + d[1] * d[1]).sqrt() * self.turn
    }
}

/// A bound on how far a law's value moves over a step of length `h` (|h|), where the law
/// has one from its form: a constant, a linear law (and either scaled).
#[inline(always)]
pub fn law_travel(law: &MotionLaw, h: f64) -> Option<f64> {
    // the two forms of every step inlined; a scaled law through the call
    match law {
        MotionLaw::Constant { .. } => Some(0.0),
        MotionLaw::Linear { rate, .. } => Some((rate * h).abs()),
        _ => scaled_travel(law, h),
    }
}

/// `law_travel` of a scaled law (a recursion, so not inlined), None for the other forms.
fn scaled_travel(law: &MotionLaw, h: f64) -> Option<f64> {
    match law {
        MotionLaw::Scaled { factor, law } => law_travel(law, h).map(|x| factor.abs() * x),
        _ => None,
    }
}

/// An RRR dyad with links r1, r2 whose known pins are `dd` = |C - A|^2 apart at the step's
/// end and moved by at most `l` = L_A + L_C over it: the bounds on its bodies' turns, or
/// None where the step may have met the singular configuration (`l` > GUARD m, or not
/// finite).
#[inline(always)]
pub fn rrr(r1: f64, r2: f64, dd: f64, l: f64) -> Option<(f64, f64)> {
    let (ok, t1, t2) = rrr_turns(r1, r2, dd, l);
    ok.then_some((t1, t2))
}

/// `rrr` without a branch (the lanes take it lane by lane): whether the step is shown,
/// and the turns (meaningless where it is not).
#[inline(always)]
pub fn rrr_turns(r1: f64, r2: f64, dd: f64, l: f64) -> (bool, f64, f64) {
    let (lo, hi) = (r1.min(r2), r1.max(r2));
    let margin = rrr_margin(r1, r2, dd);
    // NaN fails the comparison
    let ok = l <= GUARD * margin;
    // over the step the margin stays >= m: (r1 + r2 - D)(D - |r1 - r2|) >= m (2 lo - m)
    // (concave in D, least at the ends), r1 + r2 + D >= 2 hi, D + |r1 - r2| >= 2 (hi - lo) + m;
    // 16 area^2 is their product and sin = 2 area / (r1 r2)
    let m = margin - l;
    let sin = (m * (2.0 * lo - m) * (2.0 * hi) * (2.0 * (hi - lo) + m)).sqrt() / (2.0 * r1 * r2);
    (ok, l / (r1 * sin), l / (r2 * sin))
}

/// `rrr`'s test alone (no turns), where no later group reads the bodies' bounds.
#[inline(always)]
pub fn rrr_shown(r1: f64, r2: f64, dd: f64, l: f64) -> bool {
    // NaN fails the comparison
    l <= GUARD * rrr_margin(r1, r2, dd)
}

/// D's distance to the nearer of the RRR dyad's limits |r1 - r2| and r1 + r2, D^2 = `dd`.
#[inline(always)]
fn rrr_margin(r1: f64, r2: f64, dd: f64) -> f64 {
    let d = dd.sqrt();
    let (lo, hi) = (r1.min(r2), r1.max(r2));
    (r1 + r2 - d).min(d - (hi - lo))
}

/// `rrp`'s test alone (no turn), where no later group reads the bodies' bounds.
#[inline(always)]
pub fn rrp_shown(r1: f64, offset: f64, l: f64) -> bool {
    // NaN fails the comparison
    l <= GUARD * (r1 - offset.abs())
}

/// An RRP dyad on a line fixed in the ground, link r1, its known pin `offset` from the line
/// at the step's end and moved by at most `l`: the bound on the link's turn, or None (as
/// `rrr`).
#[inline(always)]
pub fn rrp(r1: f64, offset: f64, l: f64) -> Option<f64> {
    let margin = r1 - offset.abs();
    // NaN fails the comparison
    let shown = l <= GUARD * margin;
    if !shown {
        return None;
    }
    // h^2 = r1^2 - offset^2 = x (2 r1 - x) with x = r1 - |offset| >= m, x <= r1
    let m = margin - l;
    Some(l / (m * (2.0 * r1 - m)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The RRR bound on body 1's turn holds on a four-bar whose crank turns by a step:
    /// the rocker's and coupler's true turns, sampled finely, stay under the bounds; a
    /// step across the change point gets none.
    #[test]
    fn rrr_turn_bounds_hold_and_a_crossing_step_has_none() {
        // a crank of 1 about the origin, the dyad's other pin C = (4, 0), r1 = 3.5 (coupler
        // from the crank's pin A), r2 = 2.6 (rocker from C)
        let (r1, r2, c) = (3.5, 2.6, [4.0, 0.0]);
        let b_of = |phi: f64| {
            let a = [phi.cos(), phi.sin()];
            let d = sub(c, a);
            let dd = d[0] * d[0] + d[1] * d[1];
            let along = 0.5 * (dd + r1 * r1 - r2 * r2) / dd;
            let h = (r1 * r1 / dd - along * along).sqrt();
            let b = [a[0] + along * d[0] - h * d[1], a[1] + along * d[1] + h * d[0]];
            (a, b, dd)
        };
        let angle = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1]).atan2(q[0] - p[0]);
        for k in 0..36 {
            let (phi0, step) = (k as f64 * 0.17, 0.05);
            let (a1, _, dd) = b_of(phi0 + step);
            let (t1, t2) = rrr(r1, r2, dd, step).expect("far from the limits");
            // the true turns, summed over a fine subdivision
            let (mut turn1, mut turn2) = (0.0, 0.0);
            let n = 200;
            for i in 0..n {
                let (pa, pb, _) = b_of(phi0 + step * i as f64 / n as f64);
                let (qa, qb, _) = b_of(phi0 + step * (i + 1) as f64 / n as f64);
                let d1 = angle(qa, qb) - angle(pa, pb);
                let d2 = angle(c, qb) - angle(c, pb);
                turn1 += d1.abs();
                turn2 += d2.abs();
            }
            assert!(turn1 <= t1 && turn2 <= t2, "{k}: {turn1} > {t1} or {turn2} > {t2}");
            assert!(a1[0].is_finite());
        }
        // D at its largest, 5 = r1 + r2 - 1.1: a margin of 1.1; a step of 1.2 (more than
        // the margin) gets no bound, nor does one of 0.56 (more than half of it)
        assert!(rrr(r1, r2, 25.0, 1.2).is_none());
        assert!(rrr(r1, r2, 25.0, 0.56).is_none());
        assert!(rrr(r1, r2, 25.0, 0.54).is_some());
        assert!(rrr(r1, r2, f64::NAN, 0.1).is_none());
    }

    #[test]
    fn law_travel_only_where_the_form_bounds_it() {
        let lin = MotionLaw::Linear { value: 0.3, rate: -2.0 };
        assert_eq!(law_travel(&lin, 0.25), Some(0.5));
        assert_eq!(law_travel(&MotionLaw::Constant { value: 1.0 }, 0.25), Some(0.0));
        let scaled = MotionLaw::Scaled { factor: -3.0, law: Box::new(lin) };
        assert_eq!(law_travel(&scaled, 0.25), Some(1.5));
        let harmonic = MotionLaw::Harmonic { mean: 0.0, amplitude: 1.0, omega: 1.0, phase: 0.0 };
        assert_eq!(law_travel(&harmonic, 0.25), None);
    }

    /// The RRP bound on the link's turn holds on a slider-crank (crank 1, rod 3, line y = 0.5).
    #[test]
    fn rrp_turn_bound_holds() {
        let (r1, y0) = (3.0, 0.5);
        let link_angle = |phi: f64| {
            let a = [phi.cos(), phi.sin()];
            let off = y0 - a[1];
            // B on the line at height y0
            let bx = a[0] + (r1 * r1 - off * off).sqrt();
            (off.atan2(bx - a[0]), off)
        };
        for k in 0..36 {
            let (phi0, step) = (k as f64 * 0.17, 0.05);
            let (_, off) = link_angle(phi0 + step);
            let bound = rrp(r1, off, step).expect("far from tangency");
            let n = 200;
            let turn: f64 = (0..n)
                .map(|i| {
                    let p = phi0 + step * i as f64 / n as f64;
                    (link_angle(p + step / n as f64).0 - link_angle(p).0).abs()
                })
                .sum();
            assert!(turn <= bound, "{k}: {turn} > {bound}");
        }
        assert!(rrp(r1, 2.9, 0.06).is_none());
        assert!(rrp(r1, 2.9, 0.04).is_some());
    }
}
