//! Synthesis against mechanisms that generated the precision points: each generator must
//! be among the real solutions to 1e-10, every root certified, and the homotopy must
//! agree with the independent elimination (resultant.rs).

use linkwork::synthesis::motion::{
    burmester, burmester_by_resultant, four_pose_curves, three_pose_ground, three_pose_moving, Pose,
};
use linkwork::synthesis::path::{coupler_rotations, timed_dyads, timed_dyads_by_resultant};
use linkwork::synthesis::{Dyad, DyadSet, SynthesisError};
use num_complex::Complex64 as C64;

/// A four-bar: ground pivots a0, b0, crank |A - a0| = ra, coupler |B - A| = l, rocker
/// |B - b0| = rb; the coupler carries P at (u, v) in the frame of A -> B.
struct FourBar {
    a0: C64,
    b0: C64,
    ra: f64,
    l: f64,
    rb: f64,
    p: C64,
}

impl FourBar {
    fn at(&self, phi: f64) -> (C64, C64, f64, C64) {
        let a = self.a0 + C64::from_polar(self.ra, phi);
        let d = self.b0 - a;
        let dist = d.norm();
        let along = (self.l * self.l - self.rb * self.rb + dist * dist) / (2.0 * dist);
        let h = (self.l * self.l - along * along).sqrt();
        assert!(h.is_finite(), "the generator does not assemble at {phi}");
        let b = a + d / dist * C64::new(along, h);
        let angle = (b - a).arg();
        (a, b, angle, a + self.p * C64::from_polar(1.0, angle))
    }
}

fn generator() -> FourBar {
    FourBar {
        a0: C64::new(0.0, 0.0),
        b0: C64::new(4.0, 0.5),
        ra: 1.5,
        l: 4.0,
        rb: 3.0,
        p: C64::new(1.7, 1.1),
    }
}

fn near(d: &Dyad, g: C64, m: C64, tol: f64) -> bool {
    (C64::new(d.ground[0], d.ground[1]) - g).norm() < tol
        && (C64::new(d.moving[0], d.moving[1]) - m).norm() < tol
}

const PHIS: [f64; 5] = [0.3, 0.7, 1.2, 1.8, 2.3];

#[test]
fn burmester_recovers_both_dyads_of_the_generator() {
    let fb = generator();
    let poses: Vec<Pose> = PHIS
        .iter()
        .map(|&phi| {
            let (_, _, angle, p) = fb.at(phi);
            Pose { x: p.re, y: p.im, angle }
        })
        .collect();
    let set = burmester(&poses).unwrap();
    assert!(set.dyads.len() <= 4 && set.failed == 0, "{set:?}");
    assert!(set.distinct && set.dyads.iter().all(|d| d.certified));
    let (a1, b1, _, _) = fb.at(PHIS[0]);
    for (g, m) in [(fb.a0, a1), (fb.b0, b1)] {
        let hit = set.real().find(|d| near(d, g, m, 1e-10));
        let hit = hit.unwrap_or_else(|| panic!("generator dyad {g} {m} missing from {set:?}"));
        assert!(hit.residual < 1e-12, "{hit:?}");
    }
    // the elimination finds the same roots, real and complex, all certified
    agree(&set, &burmester_by_resultant(&poses).unwrap(), 1e-9);
}

/// Two solution sets of one problem hold the same roots: as many, as many real, each root
/// of `other` certified and within `tol` (relative to its size) of one of `set`.
fn agree(set: &DyadSet, other: &DyadSet, tol: f64) {
    assert_eq!(other.dyads.len(), set.dyads.len(), "{other:?} vs {set:?}");
    assert_eq!(other.real().count(), set.real().count(), "{other:?} vs {set:?}");
    assert!(other.distinct, "{other:?}");
    let parts = |d: &Dyad| [d.ground, d.moving, d.ground_imag, d.moving_imag].concat();
    for d in &other.dyads {
        assert!(d.certified, "{d:?}");
        let a = parts(d);
        let size = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let hit = set.dyads.iter().any(|e| {
            let b = parts(e);
            a.iter().zip(&b).all(|(u, v)| (u - v).abs() <= tol * size) && e.real == d.real
        });
        assert!(hit, "{d:?} not in {set:?}");
    }
}

#[test]
fn timed_path_recovers_the_input_dyad_and_then_the_four_bar() {
    let fb = generator();
    let points: Vec<[f64; 2]> = PHIS
        .iter()
        .map(|&phi| {
            let p = fb.at(phi).3;
            [p.re, p.im]
        })
        .collect();
    let input: Vec<f64> = PHIS.iter().map(|p| p - PHIS[0]).collect();
    let set = timed_dyads(&points, &input).unwrap();
    assert!(set.dyads.len() <= 4 && set.failed == 0 && set.distinct, "{set:?}");
    let (a1, b1, angle1, _) = fb.at(PHIS[0]);
    let dyad = set.real().find(|d| near(d, fb.a0, a1, 1e-10)).unwrap_or_else(|| panic!("{set:?}"));
    // its coupler rotations are the generator's, and the follower is a Burmester dyad
    let theta = coupler_rotations(&points, &input, dyad);
    for (t, &phi) in theta.iter().zip(&PHIS) {
        let want = fb.at(phi).2 - angle1;
        assert!((C64::from_polar(1.0, *t) - C64::from_polar(1.0, want)).norm() < 1e-10);
    }
    let poses: Vec<Pose> =
        points.iter().zip(&theta).map(|(p, t)| Pose { x: p[0], y: p[1], angle: *t }).collect();
    let followers = burmester(&poses).unwrap();
    assert!(followers.real().any(|d| near(d, fb.b0, b1, 1e-10)));
    agree(&set, &timed_dyads_by_resultant(&points, &input).unwrap(), 1e-9);
}

/// Random problems: homotopy and elimination agree on every real dyad.
#[test]
fn homotopy_and_elimination_agree_on_random_problems() {
    let mut rng = linkwork_homotopy::random::Rng::new(42);
    let mut total_real = 0;
    for case in 0..20 {
        let poses: Vec<Pose> = (0..5)
            .map(|_| Pose {
                x: 4.0 * rng.uniform() - 2.0,
                y: 4.0 * rng.uniform() - 2.0,
                angle: 3.0 * rng.uniform(),
            })
            .collect();
        let set = burmester(&poses).unwrap();
        assert!(set.dyads.len() <= 4 && set.failed == 0 && set.distinct, "case {case}: {set:?}");
        agree(&set, &burmester_by_resultant(&poses).unwrap(), 1e-8);
        // Burmester's count: real dyads come in an even number (0, 2 or 4)
        assert_eq!(set.real().count() % 2, 0, "case {case}");
        total_real += set.real().count();
    }
    assert!(total_real > 0);
}

#[test]
fn three_poses_circumcentre_both_ways() {
    let fb = generator();
    let phis = [0.3, 1.0, 1.9];
    let poses: Vec<Pose> = phis
        .iter()
        .map(|&phi| {
            let (_, _, angle, p) = fb.at(phi);
            Pose { x: p.re, y: p.im, angle }
        })
        .collect();
    let (a1, _, _, _) = fb.at(phis[0]);
    let d = three_pose_ground(&poses, [a1.re, a1.im]).unwrap();
    assert!(near(&d, fb.a0, a1, 1e-12), "{d:?}");
    let d = three_pose_moving(&poses, [fb.a0.re, fb.a0.im]).unwrap();
    assert!(near(&d, fb.a0, a1, 1e-12), "{d:?}");
}

#[test]
fn four_pose_curve_points_are_exact_dyads_and_pass_the_generator() {
    let fb = generator();
    let poses: Vec<Pose> = PHIS[..4]
        .iter()
        .map(|&phi| {
            let (_, _, angle, p) = fb.at(phi);
            Pose { x: p.re, y: p.im, angle }
        })
        .collect();
    let dyads = four_pose_curves(&poses, 720).unwrap();
    assert!(dyads.len() > 700);
    let p1 = C64::new(poses[0].x, poses[0].y);
    for d in &dyads {
        let g = C64::new(d.ground[0], d.ground[1]);
        let m = C64::new(d.moving[0], d.moving[1]);
        let r0 = (m - g).norm();
        for p in &poses[1..] {
            let mj = C64::new(p.x, p.y) + (m - p1) * C64::from_polar(1.0, p.angle - poses[0].angle);
            assert!(((mj - g).norm() - r0).abs() < 1e-8 * (1.0 + r0), "{d:?}");
        }
    }
    // the generator's moving pivot A1 lies on the circle-point curve: some sample is near
    let (a1, _, _, _) = fb.at(PHIS[0]);
    let closest =
        dyads.iter().map(|d| (C64::new(d.moving[0], d.moving[1]) - a1).norm()).fold(f64::INFINITY, f64::min);
    assert!(closest < 0.05, "closest {closest}");
}

#[test]
fn bad_input_is_named() {
    let p = |x: f64, a: f64| Pose { x, y: 0.0, angle: a };
    assert!(matches!(burmester(&[p(0.0, 0.0), p(1.0, 0.1)]), Err(SynthesisError::Count { got: 2, .. })));
    let same = [p(0.0, 0.0), p(1.0, 0.1), p(1.0, 0.1), p(2.0, 0.3), p(3.0, 0.2)];
    assert!(matches!(burmester(&same), Err(SynthesisError::Coincident { i: 2, j: 3, .. })));
    let nan = [p(0.0, 0.0), p(1.0, 0.1), p(f64::NAN, 0.1), p(2.0, 0.3), p(3.0, 0.2)];
    assert!(matches!(burmester(&nan), Err(SynthesisError::NotFinite { .. })));
    // a pure translation of the body on a line: Burmester still returns (no hang, no panic)
    let line: Vec<Pose> = (0..5).map(|k| p(k as f64, 0.0)).collect();
    let set = burmester(&line).unwrap();
    assert!(set.dyads.iter().all(|d| d.certified || !d.real));
    let collinear: Vec<Pose> = (0..3).map(|k| p(k as f64, 0.0)).collect();
    assert!(matches!(three_pose_ground(&collinear, [0.0, 1.0]), Err(SynthesisError::Collinear { .. })));
}

/// The source document's chained six-bar: both dyad systems solved completely, each real
/// solution satisfies its equations, and the elimination agrees.
#[test]
fn chained_six_bar_dyads_all_found_and_agree() {
    use linkwork::synthesis::sixbar::{dyad_1, dyad_2, dyads_by_resultant};
    let points = [[1.0, 2.8], [-2.8, -3.8], [-8.3, -7.3], [-8.9, -6.7], [-7.2, 3.2]];
    let q = [-3.7, 12.9];
    let o = [0.0, 0.0];
    let deg = std::f64::consts::PI / 180.0;
    let phi: Vec<f64> = [0.0, -45.0, -90.0, -150.0, -210.0].iter().map(|v| v * deg).collect();
    let theta: Vec<f64> = [0.0, 0.5, 16.5, 27.0, 27.0].iter().map(|v| v * deg).collect();
    let one = dyad_1(&points, q, &phi, &theta).unwrap();
    let two = dyad_2(&points, o, &phi, &theta).unwrap();
    for set in [&one, &two] {
        assert!(set.dyads.len() <= 4 && set.failed == 0 && set.distinct, "{set:?}");
        assert!(set.dyads.iter().all(|d| d.certified));
    }
    let [r1, r2] = dyads_by_resultant(&points, q, o, &phi, &theta).unwrap();
    agree(&one, &r1, 1e-9);
    agree(&two, &r2, 1e-9);
    // the equations themselves, in world coordinates, for every real dyad
    let rot = |v: C64, a: f64| v * C64::from_polar(1.0, a);
    let p = |k: usize| C64::new(points[k][0], points[k][1]);
    let qc = C64::new(q[0], q[1]);
    for d in one.real() {
        let (a1, b1) = (C64::new(d.ground[0], d.ground[1]), C64::new(d.moving[0], d.moving[1]));
        for n in 0..5 {
            let an = qc + rot(a1 - qc, phi[n]);
            let bn = p(n) + rot(b1 - p(0), theta[n]);
            assert!(((an - bn).norm() - (a1 - b1).norm()).abs() < 1e-10 * (a1 - b1).norm(), "{d:?}");
        }
    }
    for d in two.real() {
        let (c1, d1) = (C64::new(d.ground[0], d.ground[1]), C64::new(d.moving[0], d.moving[1]));
        for n in 0..5 {
            let dn = p(n) + rot(d1 - p(0), theta[n]);
            let cn = dn + rot(c1 - d1, phi[n]);
            assert!((cn.norm() - c1.norm()).abs() < 1e-10 * c1.norm(), "{d:?}");
        }
    }
    eprintln!(
        "six-bar: dyad 1 {} real of {}, dyad 2 {} real of {}",
        one.real().count(),
        one.dyads.len(),
        two.real().count(),
        two.dyads.len()
    );
    for d in one.real().chain(two.real()) {
        eprintln!("  {:?} {:?}", d.ground, d.moving);
    }
}

/// Dyad 2 about an output pivot O away from the origin: data from a known dyad (C on a
/// circle about O, the link DC turned by phi_n, D on the coupler), recovered by the
/// homotopy and by the elimination.
#[test]
fn chained_six_bar_dyad_2_recovers_a_known_dyad_about_any_pivot() {
    use linkwork::synthesis::sixbar::{dyad_2, dyad_2_by_resultant};
    let mut rng = linkwork_homotopy::random::Rng::new(7);
    for case in 0..5 {
        let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.uniform();
        let o = C64::new(u(-20.0, 20.0), u(-20.0, 20.0));
        let c1 = o + C64::from_polar(u(3.0, 8.0), u(0.0, std::f64::consts::TAU));
        let d1 = c1 + C64::from_polar(u(3.0, 8.0), u(0.0, std::f64::consts::TAU));
        let p1 = d1 + C64::from_polar(u(1.0, 5.0), u(0.0, std::f64::consts::TAU));
        let (mut phi, mut theta, mut psi) = (vec![0.0], vec![0.0], vec![0.0]);
        for n in 1..5 {
            phi.push(phi[n - 1] + u(0.2, 0.6));
            theta.push(theta[n - 1] + u(-0.2, 0.2));
            psi.push(psi[n - 1] + u(0.1, 0.4));
        }
        // C_n on its circle about O (rocker angle psi_n), then D_n and P_n back along the chain
        let points: Vec<[f64; 2]> = (0..5)
            .map(|n| {
                let cn = o + (c1 - o) * C64::from_polar(1.0, psi[n]);
                let dn = cn - (c1 - d1) * C64::from_polar(1.0, phi[n]);
                let pn = dn + (p1 - d1) * C64::from_polar(1.0, theta[n]);
                [pn.re, pn.im]
            })
            .collect();
        for set in [
            dyad_2(&points, [o.re, o.im], &phi, &theta).unwrap(),
            dyad_2_by_resultant(&points, [o.re, o.im], &phi, &theta).unwrap(),
        ] {
            assert!(set.real().any(|d| near(d, c1, d1, 1e-9)), "case {case}: {set:?}");
        }
    }
}
