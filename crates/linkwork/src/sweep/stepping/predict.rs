//! The cheap path's prediction of q at the next time, from the steps before it.

use crate::model::data::Data;

/// How `predict` extrapolates q to the next time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// q + h qd + h^2/2 qdd + h^3/6 jerk, the jerk from the last two accelerations
    Jerk,
    /// q + h qd + h^2/2 qdd, qdd from the last two velocities
    Acceleration,
    /// the quadratic through the last three positions
    Quadratic,
    /// the cubic through the last four positions
    Cubic,
}

/// Predicts q at times[k] from the previous steps, by what the sweep computes: with
/// accelerations `Jerk`, with velocities `Acceleration`, positions only `Cubic`.
/// Their local errors are O(h^3) (`Acceleration`) or O(h^4) (`Jerk`, `Cubic`: with
/// positions only, a quadratic's O(h^3) left 15 % of a fine sweep's steps needing a
/// second Newton iteration), so that most steps take one Newton iteration. After a step close to a singular
/// configuration, whose rates are ill-determined (and may point along the other branch),
/// the sweep asks for `Quadratic`: positions only, and of low order, as the last
/// positions may be packed close there (a higher order amplifies their round-off).
/// Reads data.q, qd, qdd (step k-1) and the history; shifts the history.
pub fn predict(data: &mut Data, times: &[f64], k: usize, predictor: Predictor) {
    let t = times[k];
    let t1 = times[k - 1];
    let h = t - t1;
    let h1 = if k >= 2 { t1 - times[k - 2] } else { 0.0 };
    // Lagrange weights of the (up to) four previous positions, newest first, the same for
    // every coordinate
    let lagrange = |nodes: &[f64]| -> [f64; 4] {
        let mut w = [0.0; 4];
        for (a, &ta) in nodes.iter().enumerate() {
            w[a] = nodes
                .iter()
                .enumerate()
                .filter(|&(b, _)| b != a)
                .map(|(_, &tb)| (t - tb) / (ta - tb))
                .product();
        }
        w
    };
    let w = match (predictor, k) {
        (Predictor::Jerk | Predictor::Acceleration, _) | (_, 1) => [1.0, 0.0, 0.0, 0.0],
        (_, 2) => lagrange(&[t1, times[0]]),
        (Predictor::Quadratic, _) | (_, 3) => lagrange(&[t1, times[k - 2], times[k - 3]]),
        _ => lagrange(&[t1, times[k - 2], times[k - 3], times[k - 4]]),
    };
    let [q2, q3, q4] = &mut data.hist_q;
    for i in 0..data.q.len() {
        let q1 = data.q[i];
        let p = match predictor {
            Predictor::Jerk => {
                let jerk = if k >= 2 { (data.qdd[i] - data.hist_qdd[i]) / h1 } else { 0.0 };
                q1 + h * (data.qd[i] + h * (0.5 * data.qdd[i] + h * jerk / 6.0))
            }
            Predictor::Acceleration => {
                let acc = if k >= 2 { (data.qd[i] - data.hist_qd[i]) / h1 } else { 0.0 };
                q1 + h * (data.qd[i] + 0.5 * h * acc)
            }
            Predictor::Quadratic | Predictor::Cubic => w[0] * q1 + w[1] * q2[i] + w[2] * q3[i] + w[3] * q4[i],
        };
        data.hist_qdd[i] = data.qdd[i];
        data.hist_qd[i] = data.qd[i];
        q4[i] = q3[i];
        q3[i] = q2[i];
        q2[i] = q1;
        data.q[i] = p;
    }
}
