//! Homotopies H(y, t), t from 0 (start) to 1 (target), tracked on projective patches.
//!
//! Each variable group g gets a homogenizing coordinate h_g and a random affine patch
//! a_g . (y_g, h_g) = 1, so paths whose affine endpoint goes to infinity stay bounded
//! (h_g -> 0) and are recognised instead of lost. y = (x_0..x_{n-1}, h_0..h_{G-1}).

use num_complex::Complex64 as C64;

use crate::polynomial::{Compiled, Polynomial, System, SystemError, Term};
use crate::random::Rng;

/// A partition of the unknowns into groups (multi-homogeneous structure). One group of
/// all unknowns is the total-degree structure.
#[derive(Clone, Debug, PartialEq)]
pub struct Groups(pub Vec<Vec<usize>>);

impl Groups {
    pub fn total_degree(n_vars: usize) -> Self {
        Groups(vec![(0..n_vars).collect()])
    }

    pub fn validate(&self, n_vars: usize) -> Result<(), SystemError> {
        let mut seen = vec![false; n_vars];
        for group in &self.0 {
            if group.is_empty() {
                return Err(SystemError::BadGroups { n_vars, why: "a group is empty".into() });
            }
            for &v in group {
                if v >= n_vars || seen[v] {
                    return Err(SystemError::BadGroups {
                        n_vars,
                        why: format!("unknown {v} is out of range or in two groups"),
                    });
                }
                seen[v] = true;
            }
        }
        if let Some(v) = seen.iter().position(|s| !s) {
            return Err(SystemError::BadGroups { n_vars, why: format!("unknown {v} is in no group") });
        }
        Ok(())
    }

    /// degrees[i][g]: degree of polynomial i in group g.
    pub fn degrees(&self, system: &System) -> Vec<Vec<u32>> {
        system.polys.iter().map(|p| self.0.iter().map(|g| p.degree_in(g)).collect()).collect()
    }
}

/// The projective lift of a system: homogenized polynomials plus one patch per group.
#[derive(Clone, Debug)]
pub struct Projective {
    pub n_vars: usize,
    pub groups: Groups,
    /// group of each unknown
    pub group_of: Vec<usize>,
    /// patch[g]: coefficients over the group's unknowns (in group order), then h_g
    pub patches: Vec<Vec<C64>>,
}

impl Projective {
    pub fn new(n_vars: usize, groups: Groups, rng: &mut Rng) -> Self {
        let mut group_of = vec![0; n_vars];
        for (g, vars) in groups.0.iter().enumerate() {
            for &v in vars {
                group_of[v] = g;
            }
        }
        let patches =
            groups.0.iter().map(|vars| (0..=vars.len()).map(|_| rng.complex_normal()).collect()).collect();
        Projective { n_vars, groups, group_of, patches }
    }

    pub fn dim(&self) -> usize {
        self.n_vars + self.groups.0.len()
    }

    /// Homogenize every polynomial of `system` (its parameters move to indices from
    /// dim() on) and append the patch equations.
    pub fn lift(&self, system: &System) -> Vec<Polynomial> {
        let n = self.n_vars;
        let n_groups = self.groups.0.len();
        let degrees = self.groups.degrees(system);
        let mut polys: Vec<Polynomial> = system
            .polys
            .iter()
            .zip(&degrees)
            .map(|(poly, d)| {
                let terms = poly
                    .terms
                    .iter()
                    .map(|term| {
                        let mut in_group = vec![0u32; n_groups];
                        let mut powers = Vec::with_capacity(term.powers.len() + n_groups);
                        for &(i, e) in &term.powers {
                            if i < n {
                                in_group[self.group_of[i]] += e;
                                powers.push((i, e));
                            } else {
                                powers.push((i + n_groups, e));
                            }
                        }
                        for g in 0..n_groups {
                            let e = d[g] - in_group[g];
                            if e > 0 {
                                powers.push((n + g, e));
                            }
                        }
                        Term { coeff: term.coeff, powers }
                    })
                    .collect();
                Polynomial { terms }
            })
            .collect();
        for (g, vars) in self.groups.0.iter().enumerate() {
            let a = &self.patches[g];
            let mut terms: Vec<Term> =
                vars.iter().enumerate().map(|(k, &v)| Term { coeff: a[k], powers: vec![(v, 1)] }).collect();
            terms.push(Term { coeff: a[vars.len()], powers: vec![(n + g, 1)] });
            terms.push(Term { coeff: C64::new(-1.0, 0.0), powers: vec![] });
            polys.push(Polynomial { terms });
        }
        polys
    }

    /// The point on the patches representing affine x.
    pub fn from_affine(&self, x: &[C64]) -> Vec<C64> {
        let n = self.n_vars;
        let mut y = vec![C64::default(); self.dim()];
        for (g, vars) in self.groups.0.iter().enumerate() {
            let a = &self.patches[g];
            let mut s = a[vars.len()];
            for (k, &v) in vars.iter().enumerate() {
                s += a[k] * x[v];
            }
            let scale = s.inv();
            for &v in vars {
                y[v] = x[v] * scale;
            }
            y[n + g] = scale;
        }
        y
    }

    /// Affine x from y, and for each group |h_g| / max |y_g| (small: at infinity).
    pub fn to_affine(&self, y: &[C64]) -> (Vec<C64>, Vec<f64>) {
        let n = self.n_vars;
        let mut x = vec![C64::default(); n];
        let mut ratios = Vec::with_capacity(self.groups.0.len());
        for (g, vars) in self.groups.0.iter().enumerate() {
            let h = y[n + g];
            let big = vars.iter().map(|&v| y[v].norm()).fold(h.norm(), f64::max);
            ratios.push(if big > 0.0 { h.norm() / big } else { 0.0 });
            for &v in vars {
                x[v] = y[v] / h;
            }
        }
        (x, ratios)
    }
}

/// Scratch buffers for one path, allocated once.
pub struct Workspace {
    pub f: Vec<C64>,
    pub df: Vec<C64>,
    pub g: Vec<C64>,
    pub dg: Vec<C64>,
    pub z: Vec<C64>,
    pub pow: Vec<C64>,
}

/// H(y, t) with its derivatives: `hy` is dim x dim row-major.
pub trait Homotopy: Sync {
    fn dim(&self) -> usize;
    fn workspace(&self) -> Workspace;
    fn eval(&self, y: &[C64], t: f64, h: &mut [C64], hy: &mut [C64], ht: &mut [C64], ws: &mut Workspace);
}

/// A linear-product start system for a multi-homogeneous structure: polynomial i is the
/// product over groups g of d_ig random linear forms in (y_g, h_g). Its roots are found by
/// linear solves, one per choice of factors (their number is the Bezout number).
pub struct LinearProducts {
    /// forms[i]: (group, coefficients over the group's unknowns then h_g)
    pub forms: Vec<Vec<(usize, Vec<C64>)>>,
}

impl LinearProducts {
    pub fn random(degrees: &[Vec<u32>], groups: &Groups, rng: &mut Rng) -> Self {
        let forms = degrees
            .iter()
            .map(|d| {
                let mut f = Vec::new();
                for (g, &dg) in d.iter().enumerate() {
                    for _ in 0..dg {
                        let coeffs = (0..=groups.0[g].len()).map(|_| rng.complex_normal()).collect();
                        f.push((g, coeffs));
                    }
                }
                f
            })
            .collect();
        LinearProducts { forms }
    }

    fn form_value(&self, proj: &Projective, g: usize, coeffs: &[C64], y: &[C64]) -> C64 {
        let vars = &proj.groups.0[g];
        let mut s = coeffs[vars.len()] * y[proj.n_vars + g];
        for (k, &v) in vars.iter().enumerate() {
            s += coeffs[k] * y[v];
        }
        s
    }

    /// Values (n) and derivatives (n x dim, row-major) at y.
    fn eval(&self, proj: &Projective, y: &[C64], g_out: &mut [C64], dg: &mut [C64]) {
        let dim = proj.dim();
        dg.fill(C64::default());
        for (i, forms) in self.forms.iter().enumerate() {
            let values: Vec<C64> = forms.iter().map(|(g, c)| self.form_value(proj, *g, c, y)).collect();
            g_out[i] = values.iter().product();
            for (k, (g, c)) in forms.iter().enumerate() {
                let others: C64 =
                    values.iter().enumerate().filter(|(j, _)| *j != k).map(|(_, v)| *v).product();
                let vars = &proj.groups.0[*g];
                for (m, &v) in vars.iter().enumerate() {
                    dg[i * dim + v] += others * c[m];
                }
                dg[i * dim + proj.n_vars + g] += others * c[vars.len()];
            }
        }
    }

    /// Every root on the patches: assign each polynomial to one group (group g receives as
    /// many polynomials as it has unknowns) and pick one of its forms in that group.
    pub fn roots(&self, proj: &Projective) -> Vec<Vec<C64>> {
        let n = proj.n_vars;
        let n_groups = proj.groups.0.len();
        let mut roots = Vec::new();
        let mut assignment = vec![0usize; n];
        let mut left: Vec<usize> = proj.groups.0.iter().map(|g| g.len()).collect();
        self.assign(proj, 0, &mut assignment, &mut left, &mut roots);
        debug_assert!(roots.iter().all(|r: &Vec<C64>| r.len() == n + n_groups));
        roots
    }

    fn assign(
        &self,
        proj: &Projective,
        i: usize,
        assignment: &mut Vec<usize>,
        left: &mut Vec<usize>,
        roots: &mut Vec<Vec<C64>>,
    ) {
        if i == proj.n_vars {
            // every choice of one form per polynomial among its forms of the assigned group
            let choices: Vec<Vec<usize>> = (0..proj.n_vars)
                .map(|p| {
                    self.forms[p]
                        .iter()
                        .enumerate()
                        .filter(|(_, (g, _))| *g == assignment[p])
                        .map(|(k, _)| k)
                        .collect()
                })
                .collect();
            let mut pick = vec![0usize; proj.n_vars];
            loop {
                if let Some(y) = self.solve_choice(proj, assignment, &choices, &pick) {
                    roots.push(y);
                }
                // odometer over the choices
                let mut k = 0;
                loop {
                    if k == proj.n_vars {
                        return;
                    }
                    pick[k] += 1;
                    if pick[k] < choices[k].len() {
                        break;
                    }
                    pick[k] = 0;
                    k += 1;
                }
            }
        }
        for g in 0..left.len() {
            if left[g] > 0 && self.forms[i].iter().any(|(fg, _)| *fg == g) {
                left[g] -= 1;
                assignment[i] = g;
                self.assign(proj, i + 1, assignment, left, roots);
                left[g] += 1;
            }
        }
    }

    fn solve_choice(
        &self,
        proj: &Projective,
        assignment: &[usize],
        choices: &[Vec<usize>],
        pick: &[usize],
    ) -> Option<Vec<C64>> {
        let n = proj.n_vars;
        let mut y = vec![C64::default(); proj.dim()];
        for (g, vars) in proj.groups.0.iter().enumerate() {
            // the group's forms plus its patch: a square system in (y_g, h_g)
            let m = vars.len() + 1;
            let mut lu = crate::linear::Lu::new(m);
            let mut rhs = vec![C64::default(); m];
            let mut row = 0;
            for p in 0..n {
                if assignment[p] == g {
                    let c = &self.forms[p][choices[p][pick[p]]].1;
                    lu.a[row * m..(row + 1) * m].copy_from_slice(c);
                    row += 1;
                }
            }
            lu.a[row * m..(row + 1) * m].copy_from_slice(&proj.patches[g]);
            rhs[row] = C64::new(1.0, 0.0);
            if lu.factorize() < 1e-12 {
                return None;
            }
            let mut scratch = vec![C64::default(); m];
            lu.solve(&mut rhs, &mut scratch);
            for (k, &v) in vars.iter().enumerate() {
                y[v] = rhs[k];
            }
            y[n + g] = rhs[vars.len()];
        }
        Some(y)
    }
}

/// H = (1 - t) gamma G(y) + t F(y) on the polynomial rows; the patch rows are shared.
pub struct StartHomotopy {
    pub proj: Projective,
    pub target: Compiled,
    pub start: LinearProducts,
    pub gamma: C64,
}

impl StartHomotopy {
    pub fn new(system: &System, groups: Groups, rng: &mut Rng) -> Result<Self, SystemError> {
        if system.n_params != 0 {
            return Err(SystemError::ParameterCount { expected: 0, got: system.n_params });
        }
        // the fields are public: a system built by hand is checked here, not mid-track
        system.validate()?;
        groups.validate(system.n_vars)?;
        let degrees = groups.degrees(system);
        let proj = Projective::new(system.n_vars, groups, rng);
        let target = Compiled::new(&proj.lift(system), proj.dim());
        let start = LinearProducts::random(&degrees, &proj.groups, rng);
        let gamma = rng.unit_complex();
        Ok(StartHomotopy { proj, target, start, gamma })
    }
}

impl Homotopy for StartHomotopy {
    fn dim(&self) -> usize {
        self.proj.dim()
    }

    fn workspace(&self) -> Workspace {
        let d = self.dim();
        Workspace {
            f: vec![C64::default(); d],
            df: vec![C64::default(); d * d],
            g: vec![C64::default(); d],
            dg: vec![C64::default(); d * d],
            z: vec![],
            pow: vec![C64::default(); self.target.pow_len],
        }
    }

    fn eval(&self, y: &[C64], t: f64, h: &mut [C64], hy: &mut [C64], ht: &mut [C64], ws: &mut Workspace) {
        let d = self.dim();
        let n = self.proj.n_vars;
        self.target.eval(y, &mut ws.f, Some(&mut ws.df), &mut ws.pow);
        self.start.eval(&self.proj, y, &mut ws.g, &mut ws.dg);
        let a = self.gamma * (1.0 - t);
        for i in 0..d {
            if i < n {
                h[i] = a * ws.g[i] + t * ws.f[i];
                ht[i] = ws.f[i] - self.gamma * ws.g[i];
                for j in 0..d {
                    hy[i * d + j] = a * ws.dg[i * d + j] + t * ws.df[i * d + j];
                }
            } else {
                h[i] = ws.f[i];
                ht[i] = C64::default();
                hy[i * d..(i + 1) * d].copy_from_slice(&ws.df[i * d..(i + 1) * d]);
            }
        }
    }
}

/// H = F(y; (1 - t) p0 + t p1): a problem class solved once at generic complex p0, then
/// any instance p1 by tracking only the generic number of paths. The parameters are
/// folded into each monomial's coefficient as a polynomial in t when the homotopy is
/// built, so a step evaluates only the unknowns' monomials (and dH/dt from the
/// coefficients' derivatives), whatever the number of parameters.
pub struct ParameterHomotopy {
    pub proj: Projective,
    /// the lifted system over y, its coefficients unused (they depend on t)
    pub system: Compiled,
    /// per term: coefficients of its t-polynomial, lowest degree first
    t_starts: Vec<usize>,
    t_coeffs: Vec<C64>,
}

/// Product of two polynomials in t (lowest degree first).
fn t_mul(a: &[C64], b: &[C64]) -> Vec<C64> {
    let mut out = vec![C64::default(); a.len() + b.len() - 1];
    for (i, u) in a.iter().enumerate() {
        for (j, v) in b.iter().enumerate() {
            out[i + j] += u * v;
        }
    }
    out
}

impl ParameterHomotopy {
    pub fn new(
        family: &System,
        groups: Groups,
        p0: Vec<C64>,
        p1: Vec<C64>,
        rng: &mut Rng,
    ) -> Result<Self, SystemError> {
        for p in [&p0, &p1] {
            if p.len() != family.n_params {
                return Err(SystemError::ParameterCount { expected: family.n_params, got: p.len() });
            }
        }
        for p in [&p0, &p1] {
            if let Some(index) = p.iter().position(|z| !(z.re.is_finite() && z.im.is_finite())) {
                return Err(SystemError::NotFiniteParameter { index });
            }
        }
        groups.validate(family.n_vars)?;
        let proj = Projective::new(family.n_vars, groups, rng);
        let dim = proj.dim();
        let lifted = proj.lift(family);
        let mut polys = Vec::with_capacity(lifted.len());
        let mut t_polys: Vec<Vec<C64>> = Vec::new();
        for (index, poly) in lifted.iter().enumerate() {
            let mut terms: Vec<Term> = Vec::new();
            let mut tp: Vec<Vec<C64>> = Vec::new();
            for term in &poly.terms {
                let mut y_powers = Vec::new();
                let mut coeff_t = vec![term.coeff];
                for &(i, e) in &term.powers {
                    if i < dim {
                        y_powers.push((i, e));
                    } else {
                        // p_k(t) = p0_k + t (p1_k - p0_k)
                        let k = i - dim;
                        let lin = [p0[k], p1[k] - p0[k]];
                        for _ in 0..e {
                            coeff_t = t_mul(&coeff_t, &lin);
                        }
                    }
                }
                match terms.iter().position(|t| t.powers == y_powers) {
                    Some(j) => {
                        let merged = &mut tp[j];
                        if merged.len() < coeff_t.len() {
                            merged.resize(coeff_t.len(), C64::default());
                        }
                        for (m, c) in merged.iter_mut().zip(&coeff_t) {
                            *m += c;
                        }
                    }
                    None => {
                        terms.push(Term { coeff: C64::new(1.0, 0.0), powers: y_powers });
                        tp.push(coeff_t);
                    }
                }
            }
            // finite parameters can still overflow a coefficient's polynomial in t
            if tp.iter().flatten().any(|c| !(c.re.is_finite() && c.im.is_finite())) {
                return Err(SystemError::NotFinite { poly: index });
            }
            polys.push(Polynomial { terms });
            t_polys.extend(tp);
        }
        let system = Compiled::new(&polys, dim);
        let mut t_starts = vec![0];
        let mut t_coeffs = Vec::new();
        for p in t_polys {
            t_coeffs.extend(p);
            t_starts.push(t_coeffs.len());
        }
        Ok(ParameterHomotopy { proj, system, t_starts, t_coeffs })
    }
}

impl Homotopy for ParameterHomotopy {
    fn dim(&self) -> usize {
        self.proj.dim()
    }

    fn workspace(&self) -> Workspace {
        let d = self.dim();
        let n_terms = self.system.n_terms();
        Workspace {
            f: vec![C64::default(); d],
            df: vec![],
            // coefficients at t and their t-derivatives
            g: vec![C64::default(); n_terms],
            dg: vec![C64::default(); n_terms],
            z: vec![],
            pow: vec![C64::default(); self.system.pow_len],
        }
    }

    fn eval(&self, y: &[C64], t: f64, h: &mut [C64], hy: &mut [C64], ht: &mut [C64], ws: &mut Workspace) {
        for (k, w) in self.t_starts.windows(2).enumerate() {
            // Horner for the value and the derivative together
            let mut v = C64::default();
            let mut dv = C64::default();
            for c in self.t_coeffs[w[0]..w[1]].iter().rev() {
                dv = dv * t + v;
                v = v * t + c;
            }
            ws.g[k] = v;
            ws.dg[k] = dv;
        }
        self.system.eval_with(y, &ws.g, Some((&ws.dg, ht)), h, Some(hy), &mut ws.pow);
    }
}
