//! Assembly of Phi, Phi_q, nu and gamma from the joints' blocks. The solver works on the
//! scaled system (D_r Phi_q D_c)(D_c^-1 x) = D_r b with D_r = 1/L on length rows and
//! D_c = L on x, y columns, so that it is dimensionless: the same mechanism in metres and
//! millimetres has the same scaled Jacobian, tolerances and pivots.

use crate::constraints::{Constraint, Frame, Rows, MAX_ROWS};
use crate::math::angle::turned;
use crate::model::data::Data;
use crate::model::{ConstraintEntry, Model};

#[inline(always)]
fn frame(frames: &[Frame], body: Option<usize>) -> &Frame {
    match body {
        Some(i) => &frames[i],
        None => &Frame::GROUND,
    }
}

/// Recomputes each body's frame (cos, sin, velocity) from q and qd. From one step to the
/// next the angles move little: cos and sin are then turned from the last ones computed
/// in full (never from turned ones, so errors cannot accumulate: each is within one ulp
/// of sin_cos, as `turned`'s test measures), which saves almost every sin_cos of a sweep.
#[inline]
pub(crate) fn update_frames(data: &mut Data) {
    for ((i, f), base) in data.frames.iter_mut().enumerate().zip(data.frame_base.iter_mut()) {
        let (q, qd) = (&data.q[3 * i..3 * i + 3], &data.qd[3 * i..3 * i + 3]);
        let (c, s) = turned(q[2], base);
        *f = Frame { r: [q[0], q[1]], theta: q[2], c, s, rd: [qd[0], qd[1]], thetad: qd[2] };
    }
}

/// Writes the scaled phi and the scaled values of Phi_q at data.q, time t.
/// Returns the inf-norm of the scaled phi (NaN if any entry is not finite).
#[inline]
pub(crate) fn position(model: &Model, data: &mut Data, t: f64) -> f64 {
    update_frames(data);
    let l = model.length_scale;
    let col = [l, l, 1.0];
    let mut norm = 0.0f64;
    for c in &model.constraints {
        let mut rows = Rows::default();
        let extra = c.extra(&data.q, &[]);
        c.kind.position(frame(&data.frames, c.body_a), frame(&data.frames, c.body_b), &extra, t, &mut rows);
        for i in 0..c.n_rows {
            let rs = c.row_scale[i];
            let p = rows.phi[i] * rs;
            data.phi[c.row0 + i] = p;
            // NaN must not vanish in max(): keep it
            norm = if p.abs() > norm || p.is_nan() { p.abs() } else { norm };
            for (j, cs) in col.iter().enumerate() {
                if c.body_a.is_some() {
                    data.jac[c.slots_a[i][j] as usize] = rows.jac_a[i][j] * rs * cs;
                }
                if c.body_b.is_some() {
                    data.jac[c.slots_b[i][j] as usize] = rows.jac_b[i][j] * rs * cs;
                }
            }
            // own coordinates are dimensionless: column scale 1
            if c.extra.is_some() {
                data.jac[c.slots_s[i] as usize] = rows.jac_s[i] * rs;
            }
        }
    }
    norm
}

fn write_rhs(c: &ConstraintEntry, v: &[f64; MAX_ROWS], rhs: &mut [f64]) {
    for i in 0..c.n_rows {
        rhs[c.row0 + i] = v[i] * c.row_scale[i];
    }
}

/// Writes the scaled nu (= -Phi_t) into data.rhs.
#[inline]
pub(crate) fn nu(model: &Model, data: &mut Data, t: f64) {
    nu_into(model, t, &mut data.rhs);
}

/// Writes the scaled nu (= -Phi_t) into `rhs` (n_rows).
#[inline]
pub(crate) fn nu_into(model: &Model, t: f64, rhs: &mut [f64]) {
    for c in &model.constraints {
        let mut v = [0.0; MAX_ROWS];
        c.kind.nu(t, &mut v);
        write_rhs(c, &v, rhs);
    }
}

/// Writes the scaled gamma into data.rhs, at data.q and data.qd.
#[inline]
pub(crate) fn gamma(model: &Model, data: &mut Data, t: f64) {
    update_frames(data);
    for c in &model.constraints {
        let mut v = [0.0; MAX_ROWS];
        let extra = c.extra(&data.q, &data.qd);
        c.kind.gamma(frame(&data.frames, c.body_a), frame(&data.frames, c.body_b), &extra, t, &mut v);
        write_rhs(c, &v, &mut data.rhs);
    }
}
