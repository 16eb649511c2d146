//! All assembly modes of a mechanism at one input: the configurations that satisfy
//! Phi(q, t) = 0 with the drivers at their values at t (a four-bar's open and crossed
//! circuits, the four circuits of a Watt or Stephenson six-bar). Found by Newton from
//! many starting guesses: the described configuration and seeded random ones whose
//! bodies take random angles and are then placed pin by pin from the ground (so every
//! joint of a spanning tree holds and only the loop closures are open), distinct
//! solutions kept. A search, not a proof: `tries` guesses, reported with the result; the
//! tests check it against the closed-form circuit counts of four-bars, slider-cranks and
//! six-bars.

use std::collections::VecDeque;
use std::f64::consts::PI;

use crate::constraints::{kinds::ConstraintKind, Frame};
use crate::model::data::Data;
use crate::model::Model;
use crate::solve::position::solve_position;
use crate::sweep::time_loop::check_times;
use crate::SolveError;

/// Two configurations closer than this (scaled: lengths / L, angles in rad, modulo a
/// turn) are the same mode; assembled ones agree to ~1e-12.
pub const SAME_MODE: f64 = 1e-6;

/// One assembly mode.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// n_coords, angles within half a turn of the reference configuration's
    pub q: Vec<f64>,
    /// sign of det Phi_q (+1 or -1; +1 for a redundant model solved anyway)
    pub det_sign: f64,
    /// smallest / largest pivot of the scaled Phi_q there
    pub pivot_ratio: f64,
}

/// The modes found, the first being the one nearest the reference configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Modes {
    pub modes: Vec<Mode>,
    /// starting guesses tried
    pub tries: usize,
    /// guesses from which Newton converged
    pub converged: usize,
}

/// Deterministic pseudo-random numbers in [0, 1) (xorshift64*), so a search repeats.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// Which columns are angles (body thetas, own curve parameters): compared mod 2 pi.
fn angular(model: &Model) -> Vec<bool> {
    (0..model.n_coords).map(|k| k >= 3 * model.n_bodies || k % 3 == 2).collect()
}

fn distance(model: &Model, angular: &[bool], p: &[f64], q: &[f64]) -> f64 {
    p.iter()
        .zip(q)
        .zip(angular)
        .zip(&model.col_scale)
        .fold(0.0f64, |m, (((a, b), ang), s)| m.max(if *ang { wrap(a - b).abs() } else { (a - b).abs() / s }))
}

/// A guess: random angles, then each body placed through a pin to a body already
/// placed (breadth first from the ground); bodies no pin reaches keep `q_ref`'s place.
fn guess(model: &Model, q_ref: &[f64], rng: &mut Rng) -> Vec<f64> {
    let mut q = q_ref.to_vec();
    for b in 0..model.n_bodies {
        q[3 * b + 2] = q_ref[3 * b + 2] + 2.0 * PI * rng.next();
    }
    for k in 3 * model.n_bodies..model.n_coords {
        q[k] = q_ref[k] + 2.0 * PI * rng.next();
    }
    let mut placed = vec![false; model.n_bodies];
    let mut queue: VecDeque<Option<usize>> = VecDeque::from([None]);
    while let Some(parent) = queue.pop_front() {
        for c in &model.constraints {
            let ConstraintKind::Revolute(r) = &c.kind else { continue };
            let (child, u_parent, u_child) = if c.body_a == parent {
                (c.body_b, r.u_a, r.u_b)
            } else if c.body_b == parent {
                (c.body_a, r.u_b, r.u_a)
            } else {
                continue;
            };
            let Some(child) = child else { continue };
            if placed[child] {
                continue;
            }
            let frame = |b: Option<usize>| match b {
                Some(i) => Frame::new([q[3 * i], q[3 * i + 1], q[3 * i + 2]], [0.0; 3]),
                None => Frame::GROUND,
            };
            let pin = frame(parent).point(u_parent);
            let arm = frame(Some(child)).rot(u_child);
            q[3 * child] = pin[0] - arm[0];
            q[3 * child + 1] = pin[1] - arm[1];
            placed[child] = true;
            queue.push_back(Some(child));
        }
    }
    q
}

/// The assembly modes at time t, from `tries` guesses around the configuration q_ref
/// (and q_ref itself, assembled first: its mode is listed first).
pub fn assembly_modes(model: &Model, q_ref: &[f64], t: f64, tries: usize) -> Result<Modes, SolveError> {
    check_times(model, &[t])?;
    let ang = angular(model);
    let mut data = Data::new(model);
    let mut modes: Vec<Mode> = Vec::new();
    let mut converged = 0;
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for k in 0..=tries {
        data.q = if k == 0 { q_ref.to_vec() } else { guess(model, q_ref, &mut rng) };
        let Ok(info) = solve_position(model, &mut data, t, 0, true) else { continue };
        converged += 1;
        // angles within half a turn of the reference, so modes read alike
        let mut q = data.q.clone();
        for (i, a) in ang.iter().enumerate() {
            if *a {
                q[i] = q_ref[i] + wrap(q[i] - q_ref[i]);
            }
        }
        if modes.iter().all(|m| distance(model, &ang, &m.q, &q) > SAME_MODE) {
            modes.push(Mode { q, det_sign: info.det_sign, pivot_ratio: info.pivot_ratio });
        }
    }
    Ok(Modes { modes, tries: tries + 1, converged })
}
