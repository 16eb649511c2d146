//! The classical linkages inside a model: four-bar loops (four pins, the ground one of
//! the links) and slider-cranks (three pins and a slider on the ground), found from the
//! joints at a configuration, with their textbook outputs: Grashof type, the input's
//! limits of motion in closed form, the circuit (open or crossed) and the transmission
//! angle. Conventions follow R. L. Norton, *Design of Machinery*, ch. 2 and 4, and
//! `linkwork.closed_form`: the crank pivot O2, the rocker pivot O4 (or the slide line),
//! angles measured counter-clockwise from the line O2 -> O4 (or the slide axis).

use std::f64::consts::PI;

use crate::constraints::{kinds::ConstraintKind, Frame};
use crate::model::Model;

/// Lengths within this fraction of the model's length scale count as equal (Grashof's
/// change point) or as zero (a degenerate loop, not reported).
pub const LENGTH_TOL: f64 = 1e-9;

/// Grashof type of a four-bar, from its input link's point of view (Norton, table 2-4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FourBarClass {
    /// Grashof, the crank (input) shortest: it turns fully, the rocker rocks
    CrankRocker,
    /// Grashof, the ground shortest: both ground-pinned links turn fully (drag link)
    DoubleCrank,
    /// Grashof, the rocker (output) shortest: the input rocks, the output turns fully
    RockerCrank,
    /// Grashof, the coupler shortest: both ground-pinned links rock, the coupler turns
    DoubleRocker,
    /// non-Grashof (s + l > p + q): no link turns fully relative to another
    TripleRocker,
    /// s + l = p + q: the links can line up, where the linkage can change circuit
    ChangePoint,
}

impl FourBarClass {
    pub fn name(self) -> &'static str {
        match self {
            FourBarClass::CrankRocker => "crank-rocker",
            FourBarClass::DoubleCrank => "double-crank",
            FourBarClass::RockerCrank => "rocker-crank",
            FourBarClass::DoubleRocker => "Grashof double-rocker",
            FourBarClass::TripleRocker => "non-Grashof triple-rocker",
            FourBarClass::ChangePoint => "change point",
        }
    }

    /// Whether the input turns a whole revolution relative to the ground.
    pub fn input_turns(self) -> bool {
        matches!(self, FourBarClass::CrankRocker | FourBarClass::DoubleCrank)
    }
}

/// Grashof's condition for a four-bar: the class and the two sums s + l, p + q.
pub fn grashof(ground: f64, crank: f64, coupler: f64, rocker: f64) -> (FourBarClass, f64, f64) {
    let links = [ground, crank, coupler, rocker];
    let (mut s, mut l) = (0, 0);
    for k in 1..4 {
        if links[k] < links[s] {
            s = k;
        }
        if links[k] > links[l] {
            l = k;
        }
    }
    let total: f64 = links.iter().sum();
    let sl = links[s] + links[l];
    let pq = total - sl;
    let class = if (sl - pq).abs() <= LENGTH_TOL * total {
        FourBarClass::ChangePoint
    } else if sl > pq {
        FourBarClass::TripleRocker
    } else {
        match s {
            0 => FourBarClass::DoubleCrank,
            1 => FourBarClass::CrankRocker,
            2 => FourBarClass::DoubleRocker,
            _ => FourBarClass::RockerCrank,
        }
    };
    (class, sl, pq)
}

/// The angles phi in [0, pi] at which a link of length `link`, pivoted at one end of a
/// base of length `base`, puts its tip at a distance within [lo, hi] of the base's other
/// end: that distance is sqrt(link^2 + base^2 - 2 link base cos phi), so the allowed phi
/// form one interval [phi_lo, phi_hi]; None if no phi is allowed.
pub fn pivot_range(link: f64, base: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
    let cos_of = |d: f64| (link * link + base * base - d * d) / (2.0 * link * base);
    // the distance grows with phi: d <= hi bounds phi above, d >= lo below
    let (c_hi, c_lo) = (cos_of(hi), cos_of(lo));
    if c_hi > 1.0 || c_lo < -1.0 {
        return None;
    }
    Some((c_lo.clamp(-1.0, 1.0).acos(), c_hi.clamp(-1.0, 1.0).acos()))
}

/// The interval around `phi` bounded by the nearest of the `boundaries` (angles taken
/// mod 2 pi) below and above it: the connected range of motion holding the current
/// angle. None without boundaries (a full turn).
fn component(phi: f64, boundaries: &[f64]) -> Option<[f64; 2]> {
    let (mut below, mut above) = (f64::INFINITY, f64::INFINITY);
    for &b in boundaries {
        // distances from phi to the boundary going down and going up, in [0, 2 pi)
        let up = (b - phi).rem_euclid(2.0 * PI);
        let down = (phi - b).rem_euclid(2.0 * PI);
        above = above.min(up);
        below = below.min(down);
    }
    boundaries.first().map(|_| [phi - below, phi + above])
}

/// The four-bar input's boundaries: phi with |A - O4| = b + c or |b - c| (+- each).
fn four_bar_boundaries(allowed: (f64, f64)) -> Vec<f64> {
    let (lo, hi) = allowed;
    let mut out = Vec::new();
    if lo > 0.0 {
        out.extend([lo, -lo]);
    }
    if hi < PI {
        out.extend([hi, -hi]);
    }
    out
}

/// A four-bar loop of a model: ground pivots O2 (crank) and O4 (rocker), coupler pins A
/// (crank-coupler) and B (coupler-rocker).
#[derive(Debug, Clone, PartialEq)]
pub struct FourBarLoop {
    /// "crank/coupler/rocker" (the bodies' names)
    pub name: String,
    /// crank, coupler, rocker (body indices)
    pub bodies: [usize; 3],
    /// the joints O2, A, B, O4
    pub joints: [String; 4],
    /// ground, crank, coupler, rocker
    pub lengths: [f64; 4],
    pub class: FourBarClass,
    /// s + l and p + q
    pub sums: [f64; 2],
    /// whether a driver sets the crank's angle (the crank is the input)
    pub driven: bool,
    /// the crank body's angle limits (None: it turns fully), around its current angle
    pub input_limits: Option<[f64; 2]>,
    /// "open" or "crossed" at this configuration (as `linkwork.closed_form.four_bar`)
    pub circuit: &'static str,
    /// the angle at B between the coupler and the rocker, in [0, pi]
    pub transmission_angle: f64,
    /// local vectors of A on the crank and on the coupler, of B on the coupler and on the
    /// rocker; world O2 and O4
    pub a_on_crank: [f64; 2],
    pub a_on_coupler: [f64; 2],
    pub b_on_coupler: [f64; 2],
    pub b_on_rocker: [f64; 2],
    pub o2: [f64; 2],
    pub o4: [f64; 2],
}

/// A slider-crank: crank pivot O (ground), crank-rod pin A, rod-slider pin B, the slider
/// on the ground along `axis`.
#[derive(Debug, Clone, PartialEq)]
pub struct SliderCrankLoop {
    /// "crank/rod/slider"
    pub name: String,
    /// crank, rod, slider (body indices)
    pub bodies: [usize; 3],
    /// the joints O, A, B and the prismatic joint
    pub joints: [String; 4],
    /// crank r, rod l, and offset e: O's signed distance from the slide line (positive
    /// on the side the axis turned by +90 degrees points to)
    pub crank: f64,
    pub rod: f64,
    pub offset: f64,
    /// whether the crank turns fully (rod >= crank + |offset|)
    pub crank_turns: bool,
    /// rod = crank + |offset|: the rod can line up with the crank across the slide line
    pub change_point: bool,
    pub driven: bool,
    /// the crank body's angle limits (None: it turns fully)
    pub input_limits: Option<[f64; 2]>,
    /// the slider pin's travel along the axis, from the foot of O on the slide line, on
    /// the circuit of this configuration (None if the crank does not turn fully)
    pub stroke: Option<[f64; 2]>,
    /// "open" (the slider ahead of the crank pin along the axis) or "crossed"
    pub circuit: &'static str,
    /// the angle between the rod and the normal to the slide axis, in [0, pi/2] (pi/2:
    /// the rod pushes along the slide)
    pub transmission_angle: f64,
    /// world axis (unit) at this configuration and O
    pub axis: [f64; 2],
    pub o: [f64; 2],
    pub a_on_crank: [f64; 2],
    pub a_on_rod: [f64; 2],
    pub b_on_rod: [f64; 2],
    pub b_on_slider: [f64; 2],
}

/// The four-bar loops and slider-cranks of a model, at configuration q.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Linkages {
    pub four_bars: Vec<FourBarLoop>,
    pub slider_cranks: Vec<SliderCrankLoop>,
}

struct Pin {
    name: String,
    a: Option<usize>,
    b: Option<usize>,
    u_a: [f64; 2],
    u_b: [f64; 2],
}

impl Pin {
    /// The other side, and the pin's local vector on `body` and on the other side.
    fn from(&self, body: Option<usize>) -> Option<(Option<usize>, [f64; 2], [f64; 2])> {
        if self.a == body {
            Some((self.b, self.u_a, self.u_b))
        } else if self.b == body {
            Some((self.a, self.u_b, self.u_a))
        } else {
            None
        }
    }
}

fn sub(p: [f64; 2], q: [f64; 2]) -> [f64; 2] {
    [p[0] - q[0], p[1] - q[1]]
}
fn norm(v: [f64; 2]) -> f64 {
    v[0].hypot(v[1])
}
fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}
fn dot(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[0] + u[1] * v[1]
}
fn angle_between(u: [f64; 2], v: [f64; 2]) -> f64 {
    cross(u, v).atan2(dot(u, v)).abs()
}

/// Finds the four-bar loops and slider-cranks of `model` at configuration q.
pub fn linkages(model: &Model, q: &[f64]) -> Linkages {
    let frame = |b: Option<usize>| match b {
        Some(i) => Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [0.0; 3]),
        None => Frame::GROUND,
    };
    let world = |b: Option<usize>, u: [f64; 2]| frame(b).point(u);
    let pins: Vec<Pin> = model
        .constraints
        .iter()
        .filter_map(|c| match &c.kind {
            ConstraintKind::Revolute(r) => {
                Some(Pin { name: c.name.clone(), a: c.body_a, b: c.body_b, u_a: r.u_a, u_b: r.u_b })
            }
            _ => None,
        })
        .collect();
    // which bodies a driver turns relative to the ground
    let driven = |body: usize| {
        model.constraints.iter().any(|c| match &c.kind {
            ConstraintKind::AngleDriver(_) => c.body_b == Some(body),
            ConstraintKind::RelativeAngleDriver(_) => {
                (c.body_a.is_none() && c.body_b == Some(body))
                    || (c.body_b.is_none() && c.body_a == Some(body))
            }
            _ => false,
        })
    };
    let small = LENGTH_TOL * model.length_scale;
    let theta = |b: usize| q[3 * b + 2];
    let mut out = Linkages::default();
    let mut seen: Vec<[usize; 4]> = Vec::new();

    for (i2, g2) in pins.iter().enumerate() {
        let Some((Some(crank), _, o2_local)) = g2.from(None) else { continue };
        // o2_local is the pivot on the crank; its world point is the ground pivot
        let o2 = world(Some(crank), o2_local);
        for (ia, pa) in pins.iter().enumerate() {
            if ia == i2 {
                continue;
            }
            let Some((Some(coupler), a_on_crank, a_on_coupler)) = pa.from(Some(crank)) else { continue };
            let a = world(Some(crank), a_on_crank);
            if norm(sub(a, o2)) <= small {
                continue;
            }
            // four-bars: the coupler pinned to a rocker pinned to the ground
            for (ib, pb) in pins.iter().enumerate() {
                if ib == ia || ib == i2 {
                    continue;
                }
                let Some((Some(rocker), b_on_coupler, b_on_rocker)) = pb.from(Some(coupler)) else {
                    continue;
                };
                if rocker == crank {
                    continue;
                }
                for (i4, g4) in pins.iter().enumerate() {
                    if [i2, ia, ib].contains(&i4) {
                        continue;
                    }
                    let Some((None, o4_local, _)) = g4.from(Some(rocker)) else { continue };
                    let mut key = [i2, ia, ib, i4];
                    key.sort();
                    if seen.contains(&key) {
                        continue;
                    }
                    let (b, o4) = (world(Some(coupler), b_on_coupler), world(Some(rocker), o4_local));
                    let lengths = [norm(sub(o4, o2)), norm(sub(a, o2)), norm(sub(b, a)), norm(sub(b, o4))];
                    if lengths.iter().any(|&l| l <= small) {
                        continue;
                    }
                    // the input is the driven side; a loop found from its rocker first is
                    // found again from its crank
                    if driven(rocker) && !driven(crank) {
                        continue;
                    }
                    seen.push(key);
                    let (class, sl, pq) = grashof(lengths[0], lengths[1], lengths[2], lengths[3]);
                    let ground_dir = sub(o4, o2);
                    let phi = cross(ground_dir, sub(a, o2)).atan2(dot(ground_dir, sub(a, o2)));
                    // A must reach B's circle about O4: |A - O4| within [|b - c|, b + c]
                    let range = pivot_range(
                        lengths[1],
                        lengths[0],
                        (lengths[2] - lengths[3]).abs(),
                        lengths[2] + lengths[3],
                    );
                    // at a change point the circles only touch where the links line up,
                    // and a shortest crank (or ground) turns through them
                    let shortest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
                    let turns_through = class == FourBarClass::ChangePoint
                        && (lengths[1] - shortest).min(lengths[0] - shortest) <= LENGTH_TOL * lengths[0];
                    let input_limits = match range {
                        _ if turns_through => None,
                        Some(r) => component(phi, &four_bar_boundaries(r)).map(|[lo, hi]| {
                            let offset = theta(crank) - phi;
                            [lo + offset, hi + offset]
                        }),
                        None => Some([theta(crank), theta(crank)]),
                    };
                    let circuit = if cross(sub(b, a), sub(o4, b)) < 0.0 { "open" } else { "crossed" };
                    let names = &model.body_names;
                    out.four_bars.push(FourBarLoop {
                        name: format!("{}/{}/{}", names[crank], names[coupler], names[rocker]),
                        bodies: [crank, coupler, rocker],
                        joints: [g2.name.clone(), pa.name.clone(), pb.name.clone(), g4.name.clone()],
                        lengths,
                        class,
                        sums: [sl, pq],
                        driven: driven(crank),
                        input_limits,
                        circuit,
                        transmission_angle: angle_between(sub(a, b), sub(o4, b)),
                        a_on_crank,
                        a_on_coupler,
                        b_on_coupler,
                        b_on_rocker,
                        o2,
                        o4,
                    });
                }
            }
            // slider-cranks: the rod pinned to a slider on the ground
            let rod = coupler;
            for (ib, pb) in pins.iter().enumerate() {
                if ib == ia || ib == i2 {
                    continue;
                }
                let Some((Some(slider), b_on_rod, b_on_slider)) = pb.from(Some(rod)) else { continue };
                if slider == crank {
                    continue;
                }
                for c in &model.constraints {
                    let ConstraintKind::Prismatic(p) = &c.kind else { continue };
                    let on_ground = match (c.body_a, c.body_b) {
                        (None, Some(s)) => s == slider,
                        (Some(s), None) => s == slider,
                        _ => false,
                    };
                    if !on_ground || (driven(slider) && !driven(crank)) {
                        continue;
                    }
                    // the axis is fixed in side a (the ground, or the slider: its angle
                    // does not change, so its world direction at q is the axis)
                    let e = frame(c.body_a).rot(p.e_a);
                    let b = world(Some(rod), b_on_rod);
                    let (r, l) = (norm(sub(a, o2)), norm(sub(b, a)));
                    if r <= small || l <= small {
                        continue;
                    }
                    let n = [-e[1], e[0]];
                    // O's signed distance from the slide line through B
                    let offset = dot(n, sub(o2, b));
                    let margin = l - r - offset.abs();
                    let change_point = margin.abs() <= LENGTH_TOL * (l + r);
                    let crank_turns = margin > 0.0 || change_point;
                    // the crank angle from the axis; B on the line needs |offset + r sin phi| <= l
                    let phi = cross(e, sub(a, o2)).atan2(dot(e, sub(a, o2)));
                    let input_limits = if crank_turns {
                        None
                    } else {
                        slider_limits(phi, r, l, offset).map(|[lo, hi]| {
                            let k = theta(crank) - phi;
                            [lo + k, hi + k]
                        })
                    };
                    let open = dot(sub(b, a), e) > 0.0;
                    let stroke = crank_turns.then(|| {
                        let (far, near) = (
                            ((l + r).powi(2) - offset * offset).sqrt(),
                            ((l - r).powi(2) - offset * offset).max(0.0).sqrt(),
                        );
                        if open {
                            [near, far]
                        } else {
                            [-far, -near]
                        }
                    });
                    let rod_dir = sub(b, a);
                    let names = &model.body_names;
                    out.slider_cranks.push(SliderCrankLoop {
                        name: format!("{}/{}/{}", names[crank], names[rod], names[slider]),
                        bodies: [crank, rod, slider],
                        joints: [g2.name.clone(), pa.name.clone(), pb.name.clone(), c.name.clone()],
                        crank: r,
                        rod: l,
                        offset,
                        crank_turns,
                        change_point,
                        driven: driven(crank),
                        input_limits,
                        stroke,
                        circuit: if open { "open" } else { "crossed" },
                        transmission_angle: angle_between(rod_dir, n)
                            .min(angle_between(rod_dir, [-n[0], -n[1]])),
                        axis: e,
                        o: o2,
                        a_on_crank,
                        a_on_rod: a_on_coupler,
                        b_on_rod,
                        b_on_slider,
                    });
                }
            }
        }
    }
    out
}

/// The crank angle interval (from the slide axis) holding `phi` over which the rod
/// reaches the slide line: |offset + r sin phi| <= l, i.e. sin phi in [lo, hi].
fn slider_limits(phi: f64, r: f64, l: f64, offset: f64) -> Option<[f64; 2]> {
    let lo = (-l - offset) / r;
    let hi = (l - offset) / r;
    let mut boundaries = Vec::new();
    if lo > -1.0 {
        boundaries.extend([lo.asin(), PI - lo.asin()]);
    }
    if hi < 1.0 {
        boundaries.extend([hi.asin(), PI - hi.asin()]);
    }
    component(phi, &boundaries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grashof_classes_follow_the_shortest_link() {
        assert_eq!(grashof(0.35, 0.20, 0.35, 0.25).0, FourBarClass::CrankRocker);
        assert_eq!(grashof(0.10, 0.30, 0.35, 0.25).0, FourBarClass::DoubleCrank);
        assert_eq!(grashof(0.35, 0.25, 0.35, 0.20).0, FourBarClass::RockerCrank);
        assert_eq!(grashof(0.35, 0.25, 0.20, 0.35).0, FourBarClass::DoubleRocker);
        assert_eq!(grashof(0.40, 0.30, 0.25, 0.20).0, FourBarClass::TripleRocker);
        assert_eq!(grashof(0.30, 0.10, 0.30, 0.10).0, FourBarClass::ChangePoint);
    }

    #[test]
    fn pivot_range_is_the_law_of_cosines() {
        // crank 0.3 on ground 0.4, tip within [0.05, 0.45] of the far end
        let (lo, hi) = pivot_range(0.3, 0.4, 0.05, 0.45).unwrap();
        let d = |phi: f64| (0.09 + 0.16 - 0.24 * phi.cos()).sqrt();
        assert!((d(lo) - 0.05).abs() < 1e-12 || lo == 0.0);
        assert!((d(hi) - 0.45).abs() < 1e-12);
        assert!(pivot_range(0.1, 1.0, 2.0, 3.0).is_none());
    }

    #[test]
    fn slider_limits_hold_the_rod_on_its_line() {
        // crank 0.1, rod 0.08, no offset: sin phi within +-0.8
        for phi in [0.2, 3.0, -3.0, -0.2] {
            let [lo, hi] = slider_limits(phi, 0.1, 0.08, 0.0).unwrap();
            assert!(lo <= phi && phi <= hi, "{phi} in [{lo}, {hi}]");
            for end in [lo, hi] {
                assert!(((0.1 * end.sin()).abs() - 0.08).abs() < 1e-12, "{phi}: {end}");
            }
        }
        // offset 0.05: 0.05 + 0.1 sin phi within +-0.08: sin phi in [-1, 0.3], one arc
        // through -pi/2 from pi - asin 0.3 to 2 pi + asin 0.3
        let [lo, hi] = slider_limits(-1.0, 0.1, 0.08, 0.05).unwrap();
        assert!(lo <= -1.0 && -1.0 <= hi);
        assert!((hi - lo - (PI + 2.0 * 0.3f64.asin())).abs() < 1e-12);
    }
}
