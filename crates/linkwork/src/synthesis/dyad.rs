//! The standard-form dyad equation every exact problem here reduces to.
//!
//! Row j (positions 2..5 against position 1), with planar vectors as complex numbers:
//! V_j = alpha_j x + beta_j and |V_j|^2 + 2 Re(V_j conj(sigma_j y)) = 0, i.e.
//! |V_j + sigma_j y| = |y|: the link y, turned by sigma_j and moved by V_j, keeps its
//! length. Unknowns x, y (2 real coordinates each); alpha, beta, sigma known per row.
//! Five-pose Burmester, the timed path dyad and both dyads of the chained six-bar are
//! instances (see motion.rs, path.rs, sixbar.rs).
//!
//! The family is solved once at generic complex parameters by a total-degree homotopy
//! (16 paths); every instance then tracks only that generic number of paths.

use std::sync::OnceLock;

use linkwork_homotopy::{solve, solve_parameter, Options, Polynomial, Solutions, System, C64};

use super::SynthesisError;

/// One row of the dyad system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DyadRow {
    pub alpha: C64,
    pub beta: C64,
    pub sigma: C64,
}

/// Unknowns x1, x2, y1, y2, then 6 parameters per row.
pub const N_VARS: usize = 4;
pub const PARAMS_PER_ROW: usize = 6;
/// Finite roots of the family at generic parameters: the paths every instance tracks.
pub const GENERIC_ROOTS: usize = 5;

fn build_family() -> System {
    let v = |i| Polynomial::var(i);
    let two = C64::new(2.0, 0.0);
    let polys = (0..4)
        .map(|j| {
            let p = |k: usize| v(N_VARS + PARAMS_PER_ROW * j + k);
            let (ar, ai, br, bi, sr, si) = (p(0), p(1), p(2), p(3), p(4), p(5));
            let (x1, x2, y1, y2) = (v(0), v(1), v(2), v(3));
            let vr = ar.mul(&x1).add(&ai.mul(&x2).scale(C64::new(-1.0, 0.0))).add(&br);
            let vi = ai.mul(&x1).add(&ar.mul(&x2)).add(&bi);
            let syr = sr.mul(&y1).add(&si.mul(&y2).scale(C64::new(-1.0, 0.0)));
            let syi = si.mul(&y1).add(&sr.mul(&y2));
            vr.mul(&vr).add(&vi.mul(&vi)).add(&vr.mul(&syr).scale(two)).add(&vi.mul(&syi).scale(two))
        })
        .collect();
    System::new(N_VARS, 4 * PARAMS_PER_ROW, polys).expect("the dyad family is square")
}

/// The family F(x, y; alpha, beta, sigma).
pub fn family() -> &'static System {
    static FAMILY: OnceLock<System> = OnceLock::new();
    FAMILY.get_or_init(build_family)
}

pub fn params(rows: &[DyadRow; 4]) -> Vec<C64> {
    let mut p = Vec::with_capacity(4 * PARAMS_PER_ROW);
    for r in rows {
        p.extend([
            C64::new(r.alpha.re, 0.0),
            C64::new(r.alpha.im, 0.0),
            C64::new(r.beta.re, 0.0),
            C64::new(r.beta.im, 0.0),
            C64::new(r.sigma.re, 0.0),
            C64::new(r.sigma.im, 0.0),
        ]);
    }
    p
}

/// Generic complex parameters and all roots of the family there.
pub struct StartSet {
    pub p0: Vec<C64>,
    pub roots: Vec<Vec<C64>>,
    pub total_degree: Solutions,
}

/// The start set, computed on first use (16 total-degree paths, a few hundred
/// microseconds) and kept for the process.
pub fn start_set() -> &'static StartSet {
    static START: OnceLock<StartSet> = OnceLock::new();
    START.get_or_init(|| {
        let mut rng = linkwork_homotopy::random::Rng::new(0x00d7_a1d5);
        let p0: Vec<C64> = (0..4 * PARAMS_PER_ROW).map(|_| rng.complex_normal()).collect();
        let system = family().specialize(&p0).expect("parameter count");
        let total_degree = solve(&system, None, &Options::default()).expect("square system");
        let roots = total_degree.roots.iter().filter(|r| r.certified).map(|r| r.x.clone()).collect();
        StartSet { p0, roots, total_degree }
    })
}

/// All isolated roots of one instance, by parameter homotopy from the start set.
/// Refused (not a panic) when a row's parameters are not finite or a row vanishes.
pub fn solve_rows(rows: &[DyadRow; 4]) -> Result<Solutions, SynthesisError> {
    let start = start_set();
    let p1 = params(rows);
    let opts = tracking();
    let first = solve_parameter(family(), &start.p0, &start.roots, &p1, &opts)?;
    // an instance (|sigma_j| = 1) sends exactly one of the 5 generic paths to infinity
    // unless it is special; more means a path to a finite root was taken for one
    if first.duplicates == 0 && first.failed == 0 && first.singular.is_empty() && first.at_infinity <= 1 {
        return Ok(first);
    }
    // two paths met (one jumped), one was lost, or one more went to infinity: track again,
    // ten times more carefully, from another patch; keep whichever found more roots
    let mut careful = opts;
    careful.seed ^= 0x0a11_0ade;
    careful.track.max_correction /= 10.0;
    careful.track.max_step /= 4.0;
    let second = solve_parameter(family(), &start.p0, &start.roots, &p1, &careful)?;
    Ok(if second.roots.len() > first.roots.len() { second } else { first })
}

/// Five paths are cheap: track them with steps that keep each prediction within 0.1 % of
/// the path's size, so that paths passing close to each other (nearly coincident
/// precision positions) do not jump.
fn tracking() -> Options {
    let mut opts = Options::default();
    opts.track.max_correction = 1e-3;
    opts.track.max_step = 0.1;
    // dyads 10^4 times the problem's size are roots, not infinity (the endgame then
    // judges a path diverging only below 3e-5 of its size)
    opts.infinity = 1e-12;
    opts
}

/// Residual of the four equations at (x, y) given as real planar vectors.
pub fn residuals(rows: &[DyadRow; 4], x: C64, y: C64) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (o, r) in out.iter_mut().zip(rows) {
        let v = r.alpha * x + r.beta;
        *o = (v + r.sigma * y).norm_sqr() - y.norm_sqr();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generic_family_has_five_certified_roots() {
        // with sigma free (not of unit modulus) the family has 5 finite roots; every
        // problem instance (|sigma| = 1) has at most 4, the fifth path going to infinity
        let start = start_set();
        assert_eq!(start.total_degree.paths, 16);
        assert_eq!(start.total_degree.failed, 0, "{:?}", start.total_degree);
        assert_eq!(start.total_degree.at_infinity, 11);
        assert_eq!(start.roots.len(), GENERIC_ROOTS, "{:?}", start.total_degree);
        assert!(start.total_degree.distinct);
        // the same count from other gammas and patches
        let system = family().specialize(&start.p0).unwrap();
        for seed in [1, 2, 3] {
            let opts = Options { seed, ..Options::default() };
            let again = solve(&system, None, &opts).unwrap();
            assert_eq!(again.roots.len(), GENERIC_ROOTS, "seed {seed}");
        }
    }
}
