//! The plan of a structured model: its groups in solving order, each with the method that
//! solves it and the numbers that method reads (compiled once, `crate::solve::closed_form`
//! makes and runs it), and the plan's mutable state in `Data` (`Work`).

/// One group, with how it is solved.
#[derive(Debug, Clone)]
pub enum Block {
    Crank(Crank),
    Rrr(Rrr),
    Rrp(Rrp),
    Rpr(Rpr),
    Affine(Affine),
    Newton(NewtonBlock),
}

/// The groups in solving order, each with its method.
#[derive(Debug, Clone)]
pub struct Plan {
    pub blocks: Vec<Block>,
    /// the Newton blocks' sizes, in block order (their workspaces)
    pub(crate) newton_sizes: Vec<usize>,
}

/// A model's plan, or why it is solved by the general path.
pub type PlanResult = Result<Plan, String>;

/// The mutable state of a plan: each block's branch sign and recent closeness, the
/// Newton blocks' workspaces. Lives in `Data`.
#[derive(Debug, Clone, Default)]
pub struct Work {
    /// per block: the sign of its branch (+1 or -1; 1 for blocks without branches)
    pub sign: Vec<f64>,
    /// per block: closeness to singular at the last accepted step and its rate (d/dt)
    pub close: Vec<[f64; 2]>,
    /// per block: this step's closeness and rate, kept once every group has passed
    pub next: Vec<[f64; 2]>,
    /// per Newton block
    pub newton: Vec<NewtonWork>,
    /// sign of det Phi_q over the product of the blocks' signs (a constant of the row and
    /// column order), read where the general path last factored Phi_q
    pub det_factor: f64,
    /// n_coords: the sweep's predicted q, restored when a structured step misses
    pub q_pred: Vec<f64>,
    /// n_coords each: spare buffers swapped with qd, qdd while a closed-form step is tried,
    /// holding the previous step's (swapped back on a miss; the predictor's history on
    /// success); between steps their contents mean nothing
    pub qd_prev: Vec<f64>,
    pub qdd_prev: Vec<f64>,
}

impl Work {
    pub fn new(plan: Option<&Plan>, n_coords: usize) -> Work {
        let Some(plan) = plan else { return Work::default() };
        Work {
            sign: vec![1.0; plan.blocks.len()],
            close: vec![[1.0, 0.0]; plan.blocks.len()],
            next: vec![[1.0, 0.0]; plan.blocks.len()],
            newton: plan.newton_sizes.iter().map(|&n| NewtonWork::new(n)).collect(),
            det_factor: 1.0,
            q_pred: vec![0.0; n_coords],
            qd_prev: vec![0.0; n_coords],
            qdd_prev: vec![0.0; n_coords],
        }
    }
}

#[derive(Debug, Clone)]
pub struct Crank {
    pub body: usize,
    /// the driver (index into model.constraints)
    pub driver: usize,
    /// theta = theta_base + sign f(t)
    pub(crate) base: Option<usize>,
    pub(crate) sign: f64,
    /// the pin: the known side and the pin in its frame, the pin in the body's frame
    pub(crate) known: Option<usize>,
    pub(crate) u_known: [f64; 2],
    pub(crate) u_body: [f64; 2],
    /// the pin where the known side is the ground (`Frame::GROUND.point(u_known)`)
    pub(crate) fixed: [f64; 2],
    /// the pin (constraint index) and where u_known and u_body start in its numbers
    pub(crate) pin: (usize, usize, usize),
}

/// One link of a dyad: a body with its pin to the known side and its middle pin.
#[derive(Debug, Clone)]
pub(crate) struct Link {
    pub body: usize,
    /// the known side and the outer pin in its frame
    pub known: Option<usize>,
    pub u_known: [f64; 2],
    /// the outer and the middle pin in the body's frame
    pub u_outer: [f64; 2],
    pub u_middle: [f64; 2],
    /// |u_middle - u_outer| and that direction in the body's frame
    pub length: f64,
    pub inv_length: f64,
    pub dir: [f64; 2],
    /// the outer pin where the known side is the ground (`Frame::GROUND.point(u_known)`):
    /// placed once, at compile
    pub fixed: [f64; 2],
    /// the compiled number each of u_known, u_outer, u_middle (x, y) is: (constraint, index
    /// in its `params_mut`); None for a coordinate no number holds (a rod's)
    pub numbers: [Option<(usize, usize)>; 6],
}

#[derive(Debug, Clone)]
pub struct Rrr {
    pub(crate) l1: Link,
    pub(crate) l2: Link,
    /// l2 is a distance joint (a massless tie rod from its known end), not a body
    pub(crate) rod: bool,
}

#[derive(Debug, Clone)]
pub struct Rrp {
    pub(crate) link: Link,
    pub(crate) slider: usize,
    /// the prismatic's known side
    pub(crate) known: Option<usize>,
    /// the slider's middle pin in its frame
    pub(crate) u_pin: [f64; 2],
    /// true: the line is fixed in the known body (the slider is the prismatic's side b);
    /// false: the line is fixed in the slider and the known body's point runs on it
    pub(crate) line_in_known: bool,
    /// the prismatic's u_a, u_b, unit axis e_a (in side a's frame) and theta0
    pub(crate) u_a: [f64; 2],
    pub(crate) u_b: [f64; 2],
    pub(crate) e_a: [f64; 2],
    pub(crate) theta0: f64,
    /// the prismatic joint (constraint index) and the numbers of u_pin (constraint, index)
    pub(crate) prismatic: usize,
    pub(crate) pin_numbers: [Option<(usize, usize)>; 2],
    /// on the ground, the line and the slider's angle never move: `line` once, at compile
    pub(crate) ground_line: Option<Line>,
}

/// The slider's angle, cos, sin; a point of B's line and its unit direction.
pub(crate) type Line = (f64, f64, f64, [f64; 2], [f64; 2]);

/// A body pinned to a known one: the known side and the pin in its frame, the pin in the
/// body's frame.
#[derive(Debug, Clone)]
pub(crate) struct Pin {
    pub(crate) body: usize,
    pub(crate) known: Option<usize>,
    pub(crate) u_known: [f64; 2],
    pub(crate) u_body: [f64; 2],
}

#[derive(Debug, Clone)]
pub struct Rpr {
    pub(crate) line: Pin,
    /// P_S: the known side and the point in its frame
    pub(crate) point: (Option<usize>, [f64; 2]),
    /// the slider (its pin to P_S), None for a point-on-line joint's point
    pub(crate) slider: Option<Pin>,
    /// the prismatic's axis in L's frame, theta0 and its cos, sin
    pub(crate) e_a: [f64; 2],
    pub(crate) theta0: f64,
    pub(crate) c0: f64,
    pub(crate) s0: f64,
    /// cross(e_a, A(theta0)(u_b - u_S) - (u_a - u_L))
    pub(crate) k: f64,
}

/// One of the group's constraints: its index and which of its sides are the group's
/// bodies (their index in `Affine::bodies`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Member {
    pub(crate) constraint: usize,
    pub(crate) side_a: Option<usize>,
    pub(crate) side_b: Option<usize>,
}

#[derive(Debug, Clone)]
pub struct Affine {
    pub(crate) bodies: Vec<usize>,
    pub(crate) members: Vec<Member>,
    /// the angle rows in solving order: (member, row, the body it gives)
    pub(crate) angles: Vec<(usize, usize, usize)>,
    /// the position rows: (member, row), 2 per body
    pub(crate) positions: Vec<(usize, usize)>,
}

#[derive(Debug, Clone)]
pub struct NewtonBlock {
    /// columns of q solved here (n)
    pub cols: Vec<usize>,
    /// constraints whose rows are here
    pub constraints: Vec<usize>,
    /// per constraint: the local column of side a's x, y, theta, side b's, and the extra
    /// coordinate (KNOWN: solved earlier, or the ground)
    pub(crate) local: Vec<[usize; 7]>,
    /// per constraint: its first local row
    pub(crate) row0: Vec<usize>,
    /// bodies with a coordinate here (their frames are refreshed as q changes)
    pub(crate) bodies: Vec<usize>,
    /// n: coordinates (= rows)
    pub n: usize,
}

/// A Newton block's buffers, allocated once.
#[derive(Debug, Clone, Default)]
pub struct NewtonWork {
    /// n x n, column-major: the scaled block of Phi_q, then its LU
    pub(crate) jac: Vec<f64>,
    pub(crate) piv: Vec<usize>,
    pub(crate) inv: Vec<f64>,
    pub(crate) rhs: Vec<f64>,
    /// sign of the block's det at the last accepted step
    pub det_sign: f64,
}

impl NewtonWork {
    pub fn new(n: usize) -> NewtonWork {
        NewtonWork {
            jac: vec![0.0; n * n],
            piv: vec![0; n],
            inv: vec![0.0; n],
            rhs: vec![0.0; n],
            det_sign: 0.0,
        }
    }
}
