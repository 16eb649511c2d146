//! All isolated roots: track every start path (in parallel), classify each endpoint
//! (finite, at infinity, singular, failed), polish finite ones on the affine system,
//! certify them by the alpha test (and real ones as real), and merge duplicates.

use num_complex::Complex64 as C64;
use rayon::prelude::*;

use crate::certify::{Affine, AlphaTest};
use crate::homotopy::{Groups, Homotopy, ParameterHomotopy, Projective, StartHomotopy};
use crate::polynomial::{System, SystemError};
use crate::random::Rng;
use crate::track::{track, PathEnd, PathStatus, TrackOptions};

#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub track: TrackOptions,
    /// Seed of gamma, the patches and the start system.
    pub seed: u64,
    /// Fewer paths than this run on the calling thread (rayon's start-up costs more than
    /// they do); more are spread over the cores.
    pub parallel_from: usize,
    /// A homogenizing coordinate below this (relative) marks an endpoint at infinity.
    pub infinity: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options { track: TrackOptions::default(), seed: 0x5eed, parallel_from: 16, infinity: 1e-8 }
    }
}

/// One finite root of the target system.
#[derive(Clone, Debug)]
pub struct Root {
    pub x: Vec<C64>,
    /// max_i |f_i(x)|
    pub residual: f64,
    /// max_i |f_i(x)| / (|c_i|_1 max(1, |x|)^d_i)
    pub backward_error: f64,
    /// |Df| |Df^{-1}| at x
    pub condition: f64,
    /// alpha test passed: a root lies within `radius` of x
    pub certified: bool,
    /// certified as a real root (x is then real)
    pub real: bool,
    pub alpha: f64,
    /// 2 beta: the distance within which the certified root lies (measured on the
    /// projective patch for a root certified there, far from the origin)
    pub radius: f64,
    /// index of the start path that ended here
    pub path: usize,
}

/// Everything the paths found.
#[derive(Clone, Debug, Default)]
pub struct Solutions {
    /// Distinct finite nonsingular roots.
    pub roots: Vec<Root>,
    /// Paths tracked.
    pub paths: usize,
    /// Endpoints at infinity.
    pub at_infinity: usize,
    /// Finite endpoints where the Jacobian is singular (not certified, not in roots).
    pub singular: Vec<Vec<C64>>,
    /// Paths that stopped before t = 1.
    pub failed: usize,
    /// Of the failed paths, those over budget (`TrackOptions::max_steps` or `deadline`;
    /// the others stopped at the smallest step).
    pub over_budget: usize,
    /// Paths that reached a root another path already reached (path jumping when the
    /// start count is the generic root count).
    pub duplicates: usize,
    /// Whether the certified roots' balls are pairwise disjoint (so they are distinct).
    pub distinct: bool,
    pub steps: usize,
    pub rejected: usize,
}

impl Solutions {
    pub fn real(&self) -> impl Iterator<Item = &Root> {
        self.roots.iter().filter(|r| r.real)
    }
}

/// All isolated roots of a parameter-free square system, from a linear-product start
/// system on the given groups (total degree when None).
pub fn solve(system: &System, groups: Option<Groups>, opts: &Options) -> Result<Solutions, SystemError> {
    let groups = groups.unwrap_or_else(|| Groups::total_degree(system.n_vars));
    let mut rng = Rng::new(opts.seed);
    let hom = StartHomotopy::new(system, groups, &mut rng)?;
    let starts = hom.start.roots(&hom.proj);
    let ends = track_all(&hom, &hom.proj, &starts, opts);
    collect(&hom.proj, Affine::new(system.clone()), ends, opts)
}

/// The parameter homotopy along the straight segment p0 -> p1, on the patch of `seed`.
fn straight(family: &System, p0: &[C64], p1: &[C64], seed: u64) -> Result<ParameterHomotopy, SystemError> {
    let groups = Groups::total_degree(family.n_vars);
    ParameterHomotopy::new(family, groups, p0.to_vec(), p1.to_vec(), &mut Rng::new(seed))
}

/// All roots at parameters p1 by parameter homotopy from the roots `starts` (affine) of
/// the same family at generic complex parameters p0.
pub fn solve_parameter(
    family: &System,
    p0: &[C64],
    starts: &[Vec<C64>],
    p1: &[C64],
    opts: &Options,
) -> Result<Solutions, SystemError> {
    let hom = straight(family, p0, p1, opts.seed)?;
    let lifted: Vec<Vec<C64>> = starts.iter().map(|x| hom.proj.from_affine(x)).collect();
    let mut ends = track_all(&hom, &hom.proj, &lifted, opts);
    // a path that failed on the straight line may have passed near the discriminant:
    // go round it through a random complex midpoint (twice at most)
    let mut detour_rng = Rng::new(opts.seed ^ 0xde70_0a5e);
    for _ in 0..2 {
        let lost: Vec<usize> = (0..ends.len())
            .filter(|&k| {
                ends[k].status == PathStatus::Failed && !diverging(&hom.proj, &ends[k].samples, opts.infinity)
            })
            .collect();
        if lost.is_empty() {
            break;
        }
        let size =
            (p1.iter().chain(p0).map(|z| z.norm_sqr()).sum::<f64>() / (2 * p1.len()).max(1) as f64).sqrt();
        let pm: Vec<C64> = p0
            .iter()
            .zip(p1)
            .map(|(a, b)| (a + b) / 2.0 + detour_rng.complex_normal() * size * 0.5)
            .collect();
        // same seed: the same patch as `hom`, so endpoints read the same way
        let first = straight(family, p0, &pm, opts.seed)?;
        let second = straight(family, &pm, p1, opts.seed)?;
        let from: Vec<Vec<C64>> = lost.iter().map(|&k| lifted[k].clone()).collect();
        let middle = track_all(&first, &first.proj, &from, opts);
        for (&k, mid) in lost.iter().zip(middle) {
            if mid.status == PathStatus::Failed {
                continue;
            }
            let end = track_all(&second, &second.proj, std::slice::from_ref(&mid.y), opts).remove(0);
            if end.status != PathStatus::Failed {
                ends[k] = PathEnd {
                    steps: ends[k].steps + mid.steps + end.steps,
                    rejected: ends[k].rejected + mid.rejected + end.rejected,
                    ..end
                };
            }
        }
    }
    // two paths that end at one root: one of them jumped (the start count is the generic
    // root count, so every root has exactly one path); track both again, more carefully
    // (once: a path that fails on the straight line and met another after its detour
    // would only fail again)
    let met = coincident(&hom.proj, &ends, opts);
    if !met.is_empty() {
        let careful = Options {
            track: TrackOptions {
                max_correction: opts.track.max_correction / 10.0,
                max_step: opts.track.max_step / 10.0,
                initial_step: opts.track.initial_step / 10.0,
                ..opts.track
            },
            ..*opts
        };
        let from: Vec<Vec<C64>> = met.iter().map(|&k| lifted[k].clone()).collect();
        for (&k, end) in met.iter().zip(track_all(&hom, &hom.proj, &from, &careful)) {
            if end.status != PathStatus::Failed {
                ends[k] = PathEnd {
                    steps: ends[k].steps + end.steps,
                    rejected: ends[k].rejected + end.rejected,
                    ..end
                };
            }
        }
    }
    let target = family.specialize(p1)?;
    collect(&hom.proj, Affine::new(target), ends, opts)
}

/// Paths whose finite endpoint another path also reached (every member of each group).
fn coincident(proj: &Projective, ends: &[PathEnd], opts: &Options) -> Vec<usize> {
    let points: Vec<(usize, Vec<C64>)> = ends
        .iter()
        .enumerate()
        .filter(|(_, e)| e.status != PathStatus::Failed)
        .filter_map(|(k, e)| {
            let (x, ratios) = proj.to_affine(&e.y);
            let finite = ratios.iter().all(|r| *r >= opts.infinity)
                && x.iter().all(|v| v.re.is_finite() && v.im.is_finite());
            finite.then_some((k, x))
        })
        .collect();
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].1[0].re.total_cmp(&points[b].1[0].re));
    let mut met = vec![false; points.len()];
    for (i, &a) in order.iter().enumerate() {
        let xa = &points[a].1;
        let size = xa.iter().map(|v| v.norm()).fold(1.0, f64::max);
        let tol = 1e-8 * size;
        for &b in &order[i + 1..] {
            let xb = &points[b].1;
            if xb[0].re - xa[0].re > tol {
                break;
            }
            if distance(xa, xb) <= tol {
                met[a] = true;
                met[b] = true;
            }
        }
    }
    (0..points.len()).filter(|&i| met[i]).map(|i| points[i].0).collect()
}

/// Affine endpoints of the paths from `starts` (roots at p0) to p1, one per start: None
/// where the path failed or went to infinity. For monodromy loops and
/// other compositions of homotopies; `solve_parameter` also certifies.
pub fn track_parameter(
    family: &System,
    p0: &[C64],
    starts: &[Vec<C64>],
    p1: &[C64],
    opts: &Options,
) -> Result<Vec<Option<Vec<C64>>>, SystemError> {
    let hom = straight(family, p0, p1, opts.seed)?;
    let lifted: Vec<Vec<C64>> = starts.iter().map(|x| hom.proj.from_affine(x)).collect();
    let ends = track_all(&hom, &hom.proj, &lifted, opts);
    Ok(ends
        .into_iter()
        .map(|end| {
            let (x, ratios) = hom.proj.to_affine(&end.y);
            let finite = ratios.iter().all(|r| *r >= opts.infinity);
            // an ill-conditioned endpoint (Singular) is kept: the caller's Newton judges it
            (end.status != PathStatus::Failed
                && finite
                && x.iter().all(|v| v.re.is_finite() && v.im.is_finite()))
            .then_some(x)
        })
        .collect())
}

/// Every path; a path that fails (not one going to infinity) is tracked again, once,
/// with steps ten times smaller and a tighter corrector, before it counts as failed.
fn track_all(hom: &dyn Homotopy, proj: &Projective, starts: &[Vec<C64>], opts: &Options) -> Vec<PathEnd> {
    let endgame = |samples: &[(f64, Vec<C64>)]| diverging(proj, samples, opts.infinity);
    let careful = TrackOptions {
        max_step: opts.track.max_step / 10.0,
        initial_step: opts.track.initial_step / 10.0,
        max_correction: opts.track.max_correction / 10.0,
        max_steps: opts.track.max_steps * 4,
        min_step: opts.track.min_step / 100.0,
        ..opts.track
    };
    let one = |y: &Vec<C64>| {
        let end = track(hom, y, &opts.track, &endgame);
        let lost = end.status == PathStatus::Failed && !diverging(proj, &end.samples, opts.infinity);
        if lost {
            let again = track(hom, y, &careful, &endgame);
            if again.status != PathStatus::Failed || diverging(proj, &again.samples, opts.infinity) {
                return PathEnd {
                    steps: end.steps + again.steps,
                    rejected: end.rejected + again.rejected,
                    ..again
                };
            }
        }
        end
    };
    if starts.len() < opts.parallel_from {
        starts.iter().map(one).collect()
    } else {
        starts.par_iter().map(one).collect()
    }
}

/// Smallest homogenizing coordinate (relative) of each endgame sample.
fn ratios(proj: &Projective, samples: &[(f64, Vec<C64>)]) -> Vec<f64> {
    samples.iter().map(|(_, y)| proj.to_affine(y).1.into_iter().fold(f64::INFINITY, f64::min)).collect()
}

/// A path goes to infinity when its smallest homogenizing coordinate has fallen by at
/// least a factor 2.5 per decade of 1 - t over the last two decades and is already small
/// (below infinity^(3/8), 1e-3 by default): h ~ (1 - t)^w with w > 0.4, extrapolating to
/// 0 at t = 1. A finite root's coordinate levels off instead.
fn diverging(proj: &Projective, samples: &[(f64, Vec<C64>)], infinity: f64) -> bool {
    if samples.len() < 3 {
        return false;
    }
    let r = ratios(proj, &samples[samples.len() - 3..]);
    r[2] < infinity.powf(0.375) && r.windows(2).all(|w| w[1] < w[0] / 2.5)
}

fn collect(
    proj: &crate::homotopy::Projective,
    affine: Affine,
    ends: Vec<PathEnd>,
    opts: &Options,
) -> Result<Solutions, SystemError> {
    let mut out = Solutions { paths: ends.len(), ..Default::default() };
    // the lifted target is square when the target is; it is refused (not a panic) when
    // a coefficient is not finite or a polynomial constant
    let patch = Affine::new(System::new(proj.dim(), 0, proj.lift(&affine.system))?);
    for (path, end) in ends.into_iter().enumerate() {
        out.steps += end.steps;
        out.rejected += end.rejected;
        let (mut x, ratios) = proj.to_affine(&end.y);
        if ratios.iter().any(|r| *r < opts.infinity) || diverging(proj, &end.samples, opts.infinity) {
            out.at_infinity += 1;
            continue;
        }
        if end.status == PathStatus::Failed {
            out.failed += 1;
            out.over_budget += end.out_of_steps as usize;
            continue;
        }
        affine.newton(&mut x, 12);
        match certify(&affine, Some((proj, &patch)), x, end.status == PathStatus::Singular, path) {
            Ok(root) => push_root(&mut out, root),
            Err(x) => out.singular.push(x),
        }
    }
    Ok(finish(out))
}

/// Certify candidate roots found some other way (an elimination, a closed form): each is
/// polished by Newton, kept if Newton converges to a root (backward error <= 1e-10),
/// alpha-tested, real ones certified real, duplicates merged. `paths` counts the
/// candidates; `singular` holds converged candidates whose Jacobian is singular.
pub fn certify_points(system: &System, candidates: Vec<Vec<C64>>) -> Solutions {
    let affine = Affine::new(system.clone());
    let mut out = Solutions { paths: candidates.len(), ..Default::default() };
    for (path, mut x) in candidates.into_iter().enumerate() {
        if x.len() != system.n_vars || !affine.newton(&mut x, 12) || affine.residual(&x).1 > 1e-10 {
            out.failed += 1;
            continue;
        }
        match certify(&affine, None, x, false, path) {
            Ok(root) => push_root(&mut out, root),
            Err(x) => out.singular.push(x),
        }
    }
    finish(out)
}

/// The alpha test at a polished point (on the projective patch, if given, when the
/// affine test fails far from the origin), then the real test. Err: a singular root.
fn certify(
    affine: &Affine,
    patch: Option<(&Projective, &Affine)>,
    mut x: Vec<C64>,
    singular_end: bool,
    path: usize,
) -> Result<Root, Vec<C64>> {
    // a nearly real point of a real system: certify it real first (most roots of the
    // problems this crate serves are), complex only if that fails
    if let Some(root) = certify_real(affine, &x, path) {
        return Ok(root);
    }
    let mut test = affine.alpha(&x);
    if !test.certified {
        // an ill-conditioned root: carry it in double-double
        let (refined, xr) = affine.alpha_refined(&x);
        if refined.certified {
            x = xr;
            test = AlphaTest { condition: test.condition, ..refined };
        }
    }
    if let (false, Some((proj, patch))) = (test.certified, patch) {
        // far from the origin the affine gamma bound grows like |x|^(D-1): certify on
        // the projective patch, where the root has coordinates of order one (radius and
        // beta are then in the patch's coordinates)
        let mut y = proj.from_affine(&x);
        if patch.newton(&mut y, 8) {
            let mut on_patch = patch.alpha(&y);
            if !on_patch.certified {
                (on_patch, y) = patch.alpha_refined(&y);
            }
            if on_patch.certified {
                x = proj.to_affine(&y).0;
                test = AlphaTest { condition: test.condition, ..on_patch };
            }
        }
    }
    if !test.certified && (singular_end || test.condition > 1e12) {
        return Err(x);
    }
    let (residual, backward_error) = affine.residual(&x);
    Ok(Root {
        x,
        residual,
        backward_error,
        condition: test.condition,
        certified: test.certified,
        real: false,
        alpha: test.alpha,
        radius: 2.0 * test.beta,
        path,
    })
}

/// A certified real root near x, if x is real to 1e-6 of its size and the system real:
/// Newton from a real point of a real system stays real, so a certified real point
/// certifies a real root.
fn certify_real(affine: &Affine, x: &[C64], path: usize) -> Option<Root> {
    let size = x.iter().map(|v| v.norm()).fold(1.0, f64::max);
    let imag = x.iter().map(|v| v.im.abs()).fold(0.0, f64::max);
    if imag > 1e-6 * size || !affine.system.is_real() {
        return None;
    }
    let mut xr: Vec<C64> = x.iter().map(|v| C64::new(v.re, 0.0)).collect();
    affine.newton(&mut xr, 12);
    let mut test = affine.alpha(&xr);
    if !test.certified {
        // Newton in double-double keeps a real point real
        (test, xr) = affine.alpha_refined(&xr);
    }
    if !test.certified || xr.iter().any(|v| v.im != 0.0) {
        return None;
    }
    let (residual, backward_error) = affine.residual(&xr);
    Some(Root {
        x: xr,
        residual,
        backward_error,
        condition: test.condition,
        certified: true,
        real: true,
        alpha: test.alpha,
        radius: 2.0 * test.beta,
        path,
    })
}

fn push_root(out: &mut Solutions, root: Root) {
    if let Some(dup) = out.roots.iter().position(|r| same_root(r, &root)) {
        out.duplicates += 1;
        // keep the better certified copy
        if !out.roots[dup].certified && root.certified {
            out.roots[dup] = root;
        }
    } else {
        out.roots.push(root);
    }
}

fn finish(mut out: Solutions) -> Solutions {
    out.distinct = out.roots.iter().all(|r| r.certified)
        && out.roots.iter().enumerate().all(|(i, a)| {
            out.roots[i + 1..].iter().all(|b| {
                let d = distance(&a.x, &b.x);
                d > a.radius + b.radius
            })
        });
    out
}

fn distance(a: &[C64], b: &[C64]) -> f64 {
    a.iter().zip(b).map(|(u, v)| (u - v).norm_sqr()).sum::<f64>().sqrt()
}

fn same_root(a: &Root, b: &Root) -> bool {
    let d = distance(&a.x, &b.x);
    let size = a.x.iter().map(|v| v.norm()).fold(1.0, f64::max);
    d <= (a.radius + b.radius).max(1e-8 * size)
}
