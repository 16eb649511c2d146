//! Alt's nine-point path problem: every four-bar whose coupler curve passes through nine
//! given points. Wampler, Morgan and Sommese's formulation in isotropic coordinates
//! (a planar vector z as the pair z, z-bar, independent over C): unknowns
//! v = (x, x^, a, a^, y, y^, b, b^, g_1..g_8, g^_1..g^_8), parameters d_j = P_j - P_0 and
//! d^_j (the conjugates for a real instance), j = 1..8:
//!
//!   D1_j: (a^ - d^_j) x g_j + (a - d_j) x^ g^_j + (a^ - x^) d_j + (a - x) d^_j - d_j d^_j = 0
//!   D2_j: the same with (y, b)
//!   D3_j: g_j g^_j + g_j + g^_j = 0          (g = theta - 1 with theta theta^ = 1)
//!
//! D1_j is |d_j + x theta_j - a|^2 = |x - a|^2: the crank pin P_0 + x (on the coupler,
//! at P_0 + x at position 0) stays at one distance from the ground pivot P_0 + a while the
//! coupler turns by theta_j. Generically 8652 regular roots, 1442 classes under the group
//! of order 6 (swap the two dyads; Roberts cognates). The classes at generic complex
//! parameters are made once by monodromy (`monodromy`, see examples/alt_start_set.rs) and
//! shipped (data/alt_start.bin); an instance tracks 1442 paths from them.

use std::collections::HashMap;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use linkwork_homotopy::random::Rng;
use linkwork_homotopy::{
    solve_parameter, track_parameter, Affine, AlphaTest, Options, Polynomial, Root, Solutions, System, C64,
};

use super::{check_scale, coincide, Frame, SynthesisError};

pub const N_VARS: usize = 24;
pub const N_PARAMS: usize = 16;
/// Classes of roots at generic parameters (Wampler, Morgan and Sommese 1992).
pub const CLASSES: usize = 1442;
/// Order of the symmetry group: dyad swap (2) times Roberts cognates (3).
pub const GROUP_ORDER: usize = 6;

// variable indices
const X: usize = 0;
const XH: usize = 1;
const A: usize = 2;
const AH: usize = 3;
const Y: usize = 4;
const YH: usize = 5;
const B: usize = 6;
const BH: usize = 7;
const G: usize = 8;
const GH: usize = 16;

fn build_family() -> System {
    let v = Polynomial::var;
    let neg = |p: &Polynomial| p.scale(C64::new(-1.0, 0.0));
    let d = |j: usize| v(N_VARS + j);
    let dh = |j: usize| v(N_VARS + 8 + j);
    let dyad = |x: usize, xh: usize, a: usize, ah: usize, j: usize| {
        // (a^ - d^) x g + (a - d) x^ g^ + (a^ - x^) d + (a - x) d^ - d d^
        let t1 = v(ah).add(&neg(&dh(j))).mul(&v(x)).mul(&v(G + j));
        let t2 = v(a).add(&neg(&d(j))).mul(&v(xh)).mul(&v(GH + j));
        let t3 = v(ah).add(&neg(&v(xh))).mul(&d(j));
        let t4 = v(a).add(&neg(&v(x))).mul(&dh(j));
        t1.add(&t2).add(&t3).add(&t4).add(&neg(&d(j).mul(&dh(j))))
    };
    let mut polys = Vec::with_capacity(N_VARS);
    for j in 0..8 {
        polys.push(dyad(X, XH, A, AH, j));
    }
    for j in 0..8 {
        polys.push(dyad(Y, YH, B, BH, j));
    }
    for j in 0..8 {
        polys.push(v(G + j).mul(&v(GH + j)).add(&v(G + j)).add(&v(GH + j)));
    }
    System::new(N_VARS, N_PARAMS, polys).expect("Alt's system is square")
}

/// The family F(v; d, d^).
pub fn family() -> &'static System {
    static FAMILY: OnceLock<System> = OnceLock::new();
    FAMILY.get_or_init(build_family)
}

/// The parameters of nine points P_0..P_8 (planar, real): d_j = P_j - P_0 and their
/// conjugates.
pub fn params(points: &[C64; 9]) -> Vec<C64> {
    let d: Vec<C64> = (1..9).map(|j| points[j] - points[0]).collect();
    d.iter().copied().chain(d.iter().map(|z| z.conj())).collect()
}

/// g, g^ from (x, x^, a, a^, y, y^, b, b^): D1_j and D2_j are linear in (g_j, g^_j).
pub fn complete(v8: &[C64; 8], p: &[C64]) -> Option<Vec<C64>> {
    let mut v = vec![C64::default(); N_VARS];
    v[..8].copy_from_slice(v8);
    for j in 0..8 {
        let (d, dh) = (p[j], p[8 + j]);
        let row = |x: C64, xh: C64, a: C64, ah: C64| {
            ([(ah - dh) * x, (a - d) * xh], -((ah - xh) * d + (a - x) * dh - d * dh))
        };
        let (r1, c1) = row(v8[0], v8[1], v8[2], v8[3]);
        let (r2, c2) = row(v8[4], v8[5], v8[6], v8[7]);
        let det = r1[0] * r2[1] - r1[1] * r2[0];
        if det.norm() == 0.0 || !det.re.is_finite() {
            return None;
        }
        v[G + j] = (c1 * r2[1] - r1[1] * c2) / det;
        v[GH + j] = (r1[0] * c2 - c1 * r2[0]) / det;
    }
    Some(v)
}

fn head(v: &[C64]) -> [C64; 8] {
    std::array::from_fn(|k| v[k])
}

/// The dyad swap: (x, a) <-> (y, b).
pub fn swap(v8: &[C64; 8]) -> [C64; 8] {
    [v8[4], v8[5], v8[6], v8[7], v8[0], v8[1], v8[2], v8[3]]
}

/// One Roberts cognate step on (x, a, y, b) (and separately on the hatted quadruple):
/// r(x, a, y, b) = ((x - a) y / (x - y), (b x - a y) / (x - y), a - x, a).
fn roberts(x: C64, a: C64, y: C64, b: C64) -> (C64, C64, C64, C64) {
    ((x - a) * y / (x - y), (b * x - a * y) / (x - y), a - x, a)
}

pub fn cognate(v8: &[C64; 8]) -> [C64; 8] {
    let (x, a, y, b) = roberts(v8[0], v8[2], v8[4], v8[6]);
    let (xh, ah, yh, bh) = roberts(v8[1], v8[3], v8[5], v8[7]);
    [x, xh, a, ah, y, yh, b, bh]
}

/// The class of a root: itself, its two Roberts cognates, and the swaps of the three.
pub fn orbit(v8: &[C64; 8]) -> Vec<[C64; 8]> {
    let c1 = cognate(v8);
    let c2 = cognate(&c1);
    vec![*v8, c1, c2, swap(v8), swap(&c1), swap(&c2)]
}

/// Classes found so far, looked up by a rounded key of each orbit member.
struct Classes {
    reps: Vec<[C64; 8]>,
    /// orbit members by rounded key, with their class
    index: HashMap<[i64; 4], Vec<([C64; 8], usize)>>,
}

impl Classes {
    fn key(v: &[C64; 8]) -> [i64; 4] {
        // x and a, rounded: exact agreement is checked on the whole vector
        let q = |z: f64| (z * 1e5).round() as i64;
        [q(v[0].re), q(v[0].im), q(v[2].re), q(v[2].im)]
    }

    /// The class (index into `reps`) whose orbit holds v.
    fn find(&self, v: &[C64; 8]) -> Option<usize> {
        let k = Self::key(v);
        let scale = v.iter().map(|z| z.norm()).fold(1.0, f64::max);
        for dx in -1..=1 {
            for dy in -1..=1 {
                let kk = [k[0] + dx, k[1] + dy, k[2], k[3]];
                if let Some(list) = self.index.get(&kk) {
                    let hit = list
                        .iter()
                        .find(|(w, _)| w.iter().zip(v).all(|(p, q)| (p - q).norm() < 1e-7 * scale));
                    if let Some((_, class)) = hit {
                        return Some(*class);
                    }
                }
            }
        }
        None
    }

    fn insert(&mut self, v: &[C64; 8]) -> bool {
        if self.find(v).is_some() {
            return false;
        }
        let class = self.reps.len();
        for w in orbit(v) {
            if w.iter().all(|z| z.re.is_finite() && z.im.is_finite()) {
                self.index.entry(Self::key(&w)).or_default().push((w, class));
            }
        }
        self.reps.push(*v);
        true
    }
}

/// A start set: generic complex parameters and one root per class there.
#[derive(Clone, Debug)]
pub struct StartSet {
    pub p0: Vec<C64>,
    pub classes: Vec<[C64; 8]>,
}

/// A random root and the generic parameters it solves: random (x, .., b^) and rotations,
/// then for each j the two dyad equations solved for (d_j, d^_j) (their difference is
/// linear, leaving a quadratic).
fn start_pair(rng: &mut Rng) -> (Vec<C64>, [C64; 8]) {
    let v8: [C64; 8] = std::array::from_fn(|_| rng.complex_normal());
    let mut p = vec![C64::default(); N_PARAMS];
    for j in 0..8 {
        let turn = std::f64::consts::TAU * rng.uniform();
        let g = C64::from_polar(1.0, turn) - 1.0;
        let gh = C64::from_polar(1.0, -turn) - 1.0;
        // D = c0 + c1 d + c2 d^ - d d^
        let coeffs =
            |x: C64, xh: C64, a: C64, ah: C64| (ah * x * g + a * xh * gh, -xh * gh + ah - xh, -x * g + a - x);
        let (c0, c1, c2) = coeffs(v8[0], v8[1], v8[2], v8[3]);
        let (e0, e1, e2) = coeffs(v8[4], v8[5], v8[6], v8[7]);
        let k0 = -(c0 - e0) / (c2 - e2);
        let k1 = -(c1 - e1) / (c2 - e2);
        // c0 + c1 d + (c2 - d)(k0 + k1 d) = 0
        let (qa, qb, qc) = (-k1, c1 + c2 * k1 - k0, c0 + c2 * k0);
        let disc = (qb * qb - 4.0 * qa * qc).sqrt();
        let d = (-qb + disc) / (2.0 * qa);
        p[j] = d;
        p[8 + j] = k0 + k1 * d;
    }
    (p, v8)
}

/// Progress of a monodromy run: (loop, classes so far, paths tracked, paths that came
/// back to p0 as certified roots).
pub type Progress<'a> = &'a mut dyn FnMut(usize, usize, usize, usize);

/// All classes at generic parameters by monodromy: loops p0 -> p1 -> p2 -> p0 through
/// random complex parameters carry the known roots to possibly new ones; every root found
/// adds its class (the group action). Stops at `target` classes, or when `patience` loops
/// in a row find nothing new (the stable-count rule).
pub fn monodromy(
    seed: u64,
    target: usize,
    patience: usize,
    max_loops: usize,
    progress: Progress,
) -> StartSet {
    let mut rng = Rng::new(seed);
    let (p0, v8) = start_pair(&mut rng);
    let set = StartSet { p0, classes: vec![v8] };
    monodromy_from(set, &mut rng, target, patience, max_loops, progress)
}

/// Monodromy continued from a (partial) start set.
pub fn monodromy_from(
    set: StartSet,
    rng: &mut Rng,
    target: usize,
    patience: usize,
    max_loops: usize,
    progress: Progress,
) -> StartSet {
    let p0 = set.p0;
    let affine = Affine::new(family().specialize(&p0).expect("parameter count"));
    let mut classes = Classes { reps: Vec::new(), index: HashMap::new() };
    for v in &set.classes {
        classes.insert(v);
    }
    let opts = Options::default();
    let mut quiet = 0;
    let size = (p0.iter().map(|z| z.norm_sqr()).sum::<f64>() / N_PARAMS as f64).sqrt();
    for lap in 0..max_loops {
        if classes.reps.len() >= target || quiet >= patience {
            break;
        }
        // loop points of p0's size, so the loop encircles the discriminant as often as not
        let p1: Vec<C64> = (0..N_PARAMS).map(|_| rng.complex_normal() * size).collect();
        let p2: Vec<C64> = (0..N_PARAMS).map(|_| rng.complex_normal() * size).collect();
        let starts: Vec<Vec<C64>> = classes.reps.iter().filter_map(|v| complete(v, &p0)).collect();
        let tracked = starts.len();
        let mut ends: Vec<Vec<C64>> = starts;
        for (from, to) in [(&p0, &p1), (&p1, &p2), (&p2, &p0)] {
            ends = track_parameter(family(), from, &ends, to, &opts)
                .expect("parameter count")
                .into_iter()
                .flatten()
                .collect();
        }
        let mut new = 0;
        let mut back = 0;
        for mut v in ends {
            // a root when Newton converges onto it (certification waits for the instance)
            if !affine.newton(&mut v, 8) || affine.residual(&v).1 > 1e-12 {
                continue;
            }
            back += 1;
            if classes.insert(&head(&v)) {
                new += 1;
            }
        }
        quiet = if new == 0 { quiet + 1 } else { 0 };
        progress(lap + 1, classes.reps.len(), tracked, back);
    }
    StartSet { p0, classes: classes.reps }
}

/// The start set carried to other generic parameters p1 (parameter homotopy from `set`),
/// one certified root per class kept; classes lost on the way are left for
/// `monodromy_from` at p1. A start set is only as good as its worst-conditioned root:
/// a root near another (p0 near the discriminant) makes its path fail at once.
pub fn reanchor(set: &StartSet, p1: &[C64]) -> StartSet {
    let starts: Vec<Vec<C64>> = set.classes.iter().filter_map(|v| complete(v, &set.p0)).collect();
    let sol = solve_parameter(family(), &set.p0, &starts, p1, &Options::default()).expect("parameter count");
    let mut classes = Classes { reps: Vec::new(), index: HashMap::new() };
    for root in sol.roots.iter().filter(|r| r.certified) {
        classes.insert(&head(&root.x));
    }
    StartSet { p0: p1.to_vec(), classes: classes.reps }
}

/// How many of a start set's roots are certified (in double, or refined in
/// double-double), the worst alpha in double (above ALPHA0: double alone does not
/// certify that root) and the worst condition number.
pub fn start_quality(set: &StartSet) -> (usize, f64, f64) {
    let affine = Affine::new(family().specialize(&set.p0).expect("parameter count"));
    let mut certified = 0;
    let (mut alpha, mut condition) = (0.0f64, 0.0f64);
    for v in set.classes.iter().filter_map(|v| complete(v, &set.p0)) {
        let mut test = affine.alpha(&v);
        if !test.certified {
            test = AlphaTest { alpha: test.alpha, ..affine.alpha_refined(&v).0 };
        }
        certified += test.certified as usize;
        alpha = alpha.max(test.alpha);
        condition = condition.max(test.condition);
    }
    (certified, alpha, condition)
}

const MAGIC: &[u8; 8] = b"LWALT\x00\x00\x01";

/// The start set as bytes: magic, p0 (16 complex), count (u64), count x 8 complex; f64
/// little-endian, real part first.
pub fn encode(set: &StartSet) -> Vec<u8> {
    let mut out = MAGIC.to_vec();
    let mut put = |z: &C64| {
        out.extend(z.re.to_le_bytes());
        out.extend(z.im.to_le_bytes());
    };
    set.p0.iter().for_each(&mut put);
    let mut bytes = (set.classes.len() as u64).to_le_bytes().to_vec();
    let mut rest = Vec::new();
    for v in &set.classes {
        for z in v {
            rest.extend(z.re.to_le_bytes());
            rest.extend(z.im.to_le_bytes());
        }
    }
    out.append(&mut bytes);
    out.append(&mut rest);
    out
}

pub fn decode(bytes: &[u8]) -> Option<StartSet> {
    if bytes.len() < 8 + N_PARAMS * 16 + 8 || &bytes[..8] != MAGIC {
        return None;
    }
    let f = |k: usize| f64::from_le_bytes(bytes[k..k + 8].try_into().expect("8 bytes"));
    let z = |k: usize| C64::new(f(k), f(k + 8));
    let p0: Vec<C64> = (0..N_PARAMS).map(|i| z(8 + 16 * i)).collect();
    let at = 8 + 16 * N_PARAMS;
    let count = u64::from_le_bytes(bytes[at..at + 8].try_into().ok()?) as usize;
    let body = at + 8;
    if bytes.len() != body + count * 8 * 16 {
        return None;
    }
    let classes = (0..count).map(|c| std::array::from_fn(|k| z(body + 16 * (8 * c + k)))).collect();
    Some(StartSet { p0, classes })
}

/// The shipped start set (data/alt_start.bin).
pub fn shipped() -> &'static StartSet {
    static SET: OnceLock<StartSet> = OnceLock::new();
    SET.get_or_init(|| {
        decode(include_bytes!("../../data/alt_start.bin")).expect("data/alt_start.bin is a start set")
    })
}

/// All classes of four-bars through nine points, by parameter homotopy from a start set.
pub fn solve_points(
    points: &[C64; 9],
    start: &StartSet,
    budget: Duration,
) -> Result<Solutions, SynthesisError> {
    solve_params(&params(points), start, budget)
}

/// All classes at any parameters p1 = (d_1..d_8, d^_1..d^_8): a complex instance when d^
/// is not the conjugate of d (then no root is a physical four-bar).
///
/// `budget` bounds the wall time (`WALL_BUDGET` by default): paths still running then
/// stop and count as failed and over budget.
///
/// Every class has exactly one path, so two roots in one orbit (a path that jumped to a
/// cognate or the swap of another class's root, which the homotopy alone cannot see)
/// send both paths round again: four times more carefully, then (twice at most) round a
/// random complex midpoint; `distinct` then also says that the roots lie in pairwise
/// different orbits.
pub fn solve_params(p1: &[C64], start: &StartSet, budget: Duration) -> Result<Solutions, SynthesisError> {
    let deadline = Instant::now() + budget;
    let options = || options(deadline);
    let starts: Vec<Vec<C64>> = start.classes.iter().filter_map(|v| complete(v, &start.p0)).collect();
    let mut sol = solve_parameter(family(), &start.p0, &starts, p1, &options())?;
    let mut rng = Rng::new(0xa17_0de7);
    for round in 0..3 {
        let met = same_orbit(&sol);
        // past the deadline every retrack would fail at once: keep what was found
        if met.is_empty() || Instant::now() >= deadline {
            break;
        }
        let from: Vec<Vec<C64>> = met.iter().map(|&k| starts[k].clone()).collect();
        let again = if round == 0 {
            let mut careful = options();
            careful.track.max_correction /= 4.0;
            careful.track.max_step /= 4.0;
            careful.track.initial_step /= 4.0;
            solve_parameter(family(), &start.p0, &from, p1, &careful)?
        } else {
            // round a random complex midpoint: another path between the same ends
            let size = (p1.iter().map(|z| z.norm_sqr()).sum::<f64>() / p1.len() as f64).sqrt();
            let pm: Vec<C64> = p1.iter().map(|z| z + rng.complex_normal() * size).collect();
            let mids = track_parameter(family(), &start.p0, &from, &pm, &options())?;
            let kept: Vec<usize> = (0..mids.len()).filter(|&i| mids[i].is_some()).collect();
            let mids: Vec<Vec<C64>> = mids.into_iter().flatten().collect();
            let mut s = solve_parameter(family(), &pm, &mids, p1, &options())?;
            s.roots.iter_mut().for_each(|r| r.path = kept[r.path]);
            s
        };
        // keep the new endpoints only if they leave fewer roots sharing an orbit (the
        // path that was right may jump on its second way)
        let mut candidate = sol.clone();
        candidate.roots.retain(|r| !met.contains(&r.path));
        candidate.roots.extend(again.roots.into_iter().map(|r| Root { path: met[r.path], ..r }));
        candidate.roots.sort_by_key(|r| r.path);
        candidate.steps += again.steps;
        candidate.rejected += again.rejected;
        // (and not when the deadline cut the round short: its failed paths would drop roots)
        if again.over_budget == 0 && same_orbit(&candidate).len() < met.len() {
            candidate.at_infinity += again.at_infinity;
            candidate.failed += again.failed;
            candidate.over_budget += again.over_budget;
            candidate.singular.extend(again.singular);
            sol = candidate;
        } else {
            sol.steps = candidate.steps;
            sol.rejected = candidate.rejected;
        }
    }
    sol.distinct = sol.distinct && same_orbit(&sol).is_empty();
    Ok(sol)
}

/// Every class of a generic instance is finite, but some are four-bars 10^5 times the
/// points' spread: the endgame judges a path at infinity only below 3e-5 of its size.
/// A path of a generic instance takes about 75 steps (points in unit size); near a
/// degenerate instance (nearly collinear points) paths wander and are retracked and
/// detoured, for minutes. So each path has `STEP_BUDGET` (its careful retrack four times
/// that) and the instance `WALL_BUDGET`: a path over either counts as failed
/// (`Solutions::over_budget`) and the instance reports what it found.
fn options(deadline: Instant) -> Options {
    let mut opts = Options { infinity: 1e-12, ..Options::default() };
    opts.track.max_steps = STEP_BUDGET;
    opts.track.deadline = Some(deadline);
    opts
}

/// Steps (accepted plus rejected) one path may take: 25 times a generic path's.
pub const STEP_BUDGET: usize = 2_000;
/// Wall time of one instance by default: ten times a generic instance's on two cores.
pub const WALL_BUDGET: Duration = Duration::from_secs(30);

/// Paths (start indices) whose root lies in the orbit of another path's root.
fn same_orbit(sol: &Solutions) -> Vec<usize> {
    let mut classes = Classes { reps: Vec::new(), index: HashMap::new() };
    let mut owner: Vec<usize> = Vec::new();
    let mut met = Vec::new();
    for r in &sol.roots {
        let v = head(&r.x);
        match classes.find(&v) {
            Some(c) => {
                met.push(owner[c]);
                met.push(r.path);
            }
            None => {
                classes.insert(&v);
                owner.push(r.path);
            }
        }
    }
    met.sort_unstable();
    met.dedup();
    met
}

/// A root is physical (a real four-bar) when each hatted unknown is the conjugate of its
/// partner. Certified so: the symmetrized point is an approximate zero (alpha test), and
/// Newton keeps a symmetric point symmetric for a real instance (d^ = conj d), so its root
/// is symmetric. Returns the symmetrized, polished root.
pub fn physical(v: &[C64], points: &[C64; 9]) -> Option<Vec<C64>> {
    let scale = v.iter().map(|z| z.norm()).fold(1.0, f64::max);
    let pairs = [(X, XH), (A, AH), (Y, YH), (B, BH)].into_iter().chain((0..8).map(|j| (G + j, GH + j)));
    let mut w = v.to_vec();
    for (i, ih) in pairs.clone() {
        if (v[i] - v[ih].conj()).norm() > 1e-6 * scale {
            return None;
        }
        let m = (v[i] + v[ih].conj()) / 2.0;
        w[i] = m;
        w[ih] = m.conj();
    }
    let affine = Affine::new(family().specialize(&params(points)).expect("parameter count"));
    affine.newton(&mut w, 6);
    for (i, ih) in pairs {
        let m = (w[i] + w[ih].conj()) / 2.0;
        w[i] = m;
        w[ih] = m.conj();
    }
    affine.alpha(&w).certified.then_some(w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_start_pair_solves_the_system_and_its_orbit_too() {
        let mut rng = Rng::new(5);
        let (p0, v8) = start_pair(&mut rng);
        let affine = Affine::new(family().specialize(&p0).unwrap());
        for w in orbit(&v8) {
            let v = complete(&w, &p0).unwrap();
            let (_, backward) = affine.residual(&v);
            assert!(backward < 1e-12, "{backward}");
        }
    }

    #[test]
    fn encode_decode_round_trip() {
        let mut rng = Rng::new(9);
        let (p0, v8) = start_pair(&mut rng);
        let set = StartSet { p0, classes: vec![v8, cognate(&v8)] };
        let back = decode(&encode(&set)).unwrap();
        assert_eq!(back.p0, set.p0);
        assert_eq!(back.classes, set.classes);
        assert!(decode(&encode(&set)[..100]).is_none());
    }
}

/// Most points a four-bar's coupler curve has on one line: the curve has degree 6 and is
/// bounded (every point lies within crank plus coupler-point distance of a ground pivot),
/// so it holds no line and meets one in at most 6 points (Bezout).
pub const MOST_ON_A_LINE: usize = 6;

/// The frame of nine points, or why no four-bar passes through them: not finite, out of
/// scale, two coincident, or more than `MOST_ON_A_LINE` on one line (then the instance
/// is degenerate and its paths wander for minutes; refused at once).
pub fn check_points(points: &[C64]) -> Result<Frame, SynthesisError> {
    if points.len() != 9 {
        return Err(SynthesisError::Count {
            problem: "Alt's nine-point path synthesis",
            got: points.len(),
            want: "exactly 9 points".into(),
        });
    }
    let frame = check_scale("the nine points", points)?;
    for i in 0..9 {
        for j in i + 1..9 {
            if coincide(points[i], points[j], &frame) {
                return Err(SynthesisError::Coincident { what: "points", i: i + 1, j: j + 1 });
            }
        }
    }
    // the line through each pair; points within 1e-9 of the data's size of it count
    let local: Vec<C64> = points.iter().map(|&p| frame.to_local(p)).collect();
    for i in 0..9 {
        for j in i + 1..9 {
            let dir = (local[j] - local[i]) / (local[j] - local[i]).norm();
            let on: Vec<usize> =
                (0..9).filter(|&k| ((local[k] - local[i]) * dir.conj()).im.abs() <= 1e-9).collect();
            if on.len() > MOST_ON_A_LINE {
                let list: Vec<String> = on.iter().map(|k| (k + 1).to_string()).collect();
                return Err(SynthesisError::Degenerate(format!(
                    "points {} lie on one line: a four-bar's coupler curve (degree 6) meets a line in at most {MOST_ON_A_LINE} points, so no four-bar passes through them",
                    list.join(", ")
                )));
            }
        }
    }
    Ok(frame)
}

/// A real four-bar from a physical root: ground pivots P_0 + a and P_0 + b, crank pins
/// P_0 + x and P_0 + y at position 0, coupler rotations arg(1 + g_j) at positions 1..8.
#[derive(Clone, Debug, PartialEq)]
pub struct AltFourBar {
    pub ground_a: C64,
    pub moving_a: C64,
    pub ground_b: C64,
    pub moving_b: C64,
    pub coupler_angles: [f64; 8],
    /// Class (index into the instance's roots) and cognate (0, 1, 2) it comes from.
    pub class: usize,
    pub cognate: usize,
}

/// Everything one instance gave: the homotopy's account and the real four-bars (three
/// cognates per physical class; the dyad swap gives the same linkage).
#[derive(Clone, Debug)]
pub struct AltResult {
    pub solutions: Solutions,
    pub physical_classes: usize,
    pub four_bars: Vec<AltFourBar>,
}

/// Every real four-bar through nine points (world units): the points are checked
/// (`check_points`) and solved centred and scaled to unit size.
pub fn four_bars(points: &[C64; 9], start: &StartSet, budget: Duration) -> Result<AltResult, SynthesisError> {
    let frame = check_points(points)?;
    let local: [C64; 9] = std::array::from_fn(|k| frame.to_local(points[k]));
    let mut out = four_bars_local(&local, start, budget)?;
    for f in &mut out.four_bars {
        for z in [&mut f.ground_a, &mut f.moving_a, &mut f.ground_b, &mut f.moving_b] {
            *z = frame.to_world(*z);
        }
    }
    Ok(out)
}

/// `four_bars` on points already in local units.
fn four_bars_local(
    points: &[C64; 9],
    start: &StartSet,
    budget: Duration,
) -> Result<AltResult, SynthesisError> {
    let solutions = solve_points(points, start, budget)?;
    let p = params(points);
    let mut four_bars = Vec::new();
    let mut physical_classes = 0;
    for (class, root) in solutions.roots.iter().enumerate() {
        let Some(w) = physical(&root.x, points) else { continue };
        physical_classes += 1;
        let c1 = cognate(&head(&w));
        let c2 = cognate(&c1);
        for (k, v8) in [head(&w), c1, c2].iter().enumerate() {
            let Some(v) = complete(v8, &p) else { continue };
            four_bars.push(AltFourBar {
                ground_a: points[0] + v[A],
                moving_a: points[0] + v[X],
                ground_b: points[0] + v[B],
                moving_b: points[0] + v[Y],
                coupler_angles: std::array::from_fn(|j| (v[G + j] + 1.0).arg()),
                class,
                cognate: k,
            });
        }
    }
    Ok(AltResult { solutions, physical_classes, four_bars })
}

#[cfg(test)]
mod shipped_tests {
    use super::*;

    /// The shipped start set: 1442 classes, each a root of the family at p0 (g, g^ by the
    /// 2 x 2 solves), pairwise in distinct classes, every one alpha-certified (the paths
    /// an instance tracks start on roots, not near them).
    #[test]
    fn the_shipped_start_set_is_complete_and_solves_the_system() {
        let set = shipped();
        assert_eq!(set.classes.len(), CLASSES);
        let affine = Affine::new(family().specialize(&set.p0).unwrap());
        let mut classes = Classes { reps: Vec::new(), index: HashMap::new() };
        for v8 in &set.classes {
            let v = complete(v8, &set.p0).expect("g from the dyad equations");
            let (_, backward) = affine.residual(&v);
            assert!(backward < 1e-10, "{backward}");
            assert!(classes.insert(v8), "two start roots in one class");
        }
        assert_eq!(start_quality(set).0, CLASSES);
    }
}
