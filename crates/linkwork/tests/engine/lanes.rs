//! Designs stepped side by side in lanes (`sweep::lanes`): every design's figures are those
//! of its own sweep by the scalar engine, bit for bit, across the Grashof limits
//! (crank-rockers, double-cranks, a design next to its change point, cranks that cannot
//! turn and stop at their limit); the lanes take every step of the designs clear of their
//! singular configurations and hand the others back at the step their groups miss.

use crate::common;

use common::{four_bar, four_bar_closed, FourBar};
use linkwork::branches::{asked_branches, sweep_on};
use linkwork::sensitivity::Parameter;
use linkwork::solve::closed_form::lanes::{Turns, LANES};
use linkwork::sweep::lanes::{fit, sweep_lanes, LaneRows};
use linkwork::{sweep_variants, Data, Model, Outputs, PointDesc, Request, SweepOutput, Variation};

const OMEGA: f64 = 5.0;
const BASE: FourBar = FourBar { r1: 0.38, r2: 0.2, r3: 0.35, r4: 0.25 };
const BASE_P: [f64; 2] = [0.3, 0.12];

/// A design: the four-bar's lengths and its coupler point (distance from A, angle from
/// A -> B).
struct Design {
    m: FourBar,
    l5: f64,
    g: f64,
}

fn design(r1: f64, r2: f64, r3: f64, r4: f64, l5: f64, g: f64) -> Design {
    Design { m: FourBar { r1, r2, r3, r4 }, l5, g }
}

/// Across the Grashof limits. The crank is O2-A (r2), the ground O2-O4 (r1).
fn designs() -> Vec<Design> {
    vec![
        // crank-rockers (the crank the shortest link)
        design(0.38, 0.2, 0.35, 0.25, 0.1, 0.4),
        design(0.45, 0.12, 0.4, 0.3, 0.2, -0.8),
        design(0.32, 0.1, 0.28, 0.3, 0.05, 1.2),
        // a double-crank (the ground the shortest link)
        design(0.1, 0.3, 0.35, 0.3, 0.15, 0.3),
        // Grashof by 1e-4: the coupler and rocker all but stretched at half a turn
        design(0.38, 0.2, 0.35, 0.2301, 0.1, 0.0),
        // not Grashof: the crank cannot turn, it stops at its limit
        design(0.41, 0.26, 0.35, 0.25, 0.1, 0.4),
        // not Grashof either (s + l = 0.58 > p + q = 0.55)
        design(0.38, 0.2, 0.3, 0.25, 0.12, -0.2),
        design(0.5, 0.18, 0.45, 0.35, 0.25, 2.0),
        design(0.36, 0.15, 0.33, 0.27, 0.08, 0.9),
        // a chunk of fewer than LANES: swept one by one
        design(0.4, 0.16, 0.37, 0.31, 0.11, -1.1),
    ]
}

/// The design's drawing at crank angle 0 (B on the open circuit, above the ground line):
/// A, B, O4, P in the world.
fn drawing(d: &Design) -> [[f64; 2]; 4] {
    let m = &d.m;
    let a = [m.r2, 0.0];
    let dx = m.r1 - m.r2;
    let along = (dx * dx + m.r3 * m.r3 - m.r4 * m.r4) / (2.0 * dx);
    let b = [a[0] + along, (m.r3 * m.r3 - along * along).sqrt()];
    let phi = (b[1] - a[1]).atan2(b[0] - a[0]) + d.g;
    [a, b, [m.r1, 0.0], [a[0] + d.l5 * phi.cos(), a[1] + d.l5 * phi.sin()]]
}

fn times(n: usize) -> Vec<f64> {
    let turn = std::f64::consts::TAU / OMEGA;
    (0..n).map(|k| turn * k as f64 / n as f64).collect()
}

struct Setup {
    model: Model,
    variation: Variation,
    deltas: Vec<f64>,
    outputs: Outputs,
    named: Vec<Option<usize>>,
}

fn setup(designs: &[Design]) -> Setup {
    let mut desc = four_bar(&BASE, 0.0, OMEGA);
    desc.points.push(PointDesc { name: "P".into(), body: "coupler".into(), at: BASE_P });
    let model = Model::new(desc).unwrap();
    let names = [
        "joints.A.at.0",
        "joints.B.at.0",
        "joints.B.at.1",
        "joints.O4.at.0",
        "points.P.at.0",
        "points.P.at.1",
    ];
    let params = names.iter().map(|p| Parameter::resolve(&model, p).unwrap()).collect();
    let variation = Variation::new(&model, params);
    let base = drawing(&Design { m: BASE, l5: 0.0, g: 0.0 });
    let deltas = designs
        .iter()
        .flat_map(|d| {
            let [a, b, o4, p] = drawing(d);
            [
                a[0] - base[0][0],
                b[0] - base[1][0],
                b[1] - base[1][1],
                o4[0] - base[2][0],
                p[0] - BASE_P[0],
                p[1] - BASE_P[1],
            ]
        })
        .collect();
    let coupler = model.body_index("coupler").unwrap();
    let rocker = model.body_index("rocker").unwrap();
    let k = model.points.iter().position(|p| p.name == "P").unwrap();
    // the rocker's angle, and the coupler point (named: it moves with the design) and a
    // point of the rocker at a fixed place in it
    let outputs = Outputs {
        coords: Some(vec![3 * rocker + 2]),
        points: vec![(Some(coupler), model.points[k].local), (Some(rocker), [0.05, 0.01])],
    };
    Setup { model, variation, deltas, outputs, named: vec![Some(k), None] }
}

/// Design i swept alone by the scalar engine, on the branches the base is asked for.
fn alone(s: &Setup, i: usize, t: &[f64], request: Request) -> (SweepOutput, Option<String>) {
    let m = s.variation.params.len();
    let design = s.variation.model(&s.model, &s.deltas[i * m..(i + 1) * m]);
    let mut outputs = s.outputs.clone();
    for (slot, k) in outputs.points.iter_mut().zip(&s.named) {
        if let Some(k) = k {
            slot.1 = design.points[*k].local;
        }
    }
    let asked = asked_branches(&s.model, t[0]);
    let mut data = Data::new(&design);
    let mut out = SweepOutput::with_outputs(&design, t, request, outputs);
    let err = sweep_on(&design, &mut data, t, &mut out, 0, &mut |_| true, asked.as_ref()).err();
    out.truncate();
    (out, err.map(|e| format!("{e:?}")))
}

/// How far a design the lanes take may be from its sweep alone (kept angle, radians;
/// points, m): the two start apart by the last Newton correction's round-off.
const LANE_START: f64 = 1e-14;

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// The batch against every design's own sweep: steps done, the error and the events the
/// same; the kept angle, both points and the smallest pivot ratio the same bits for the
/// designs swept one by one (a lane that missed, a chunk of fewer than LANES), and for
/// the designs the lanes take to the end within `LANE_START` of them: a lane starts from
/// its closed forms where a sweep alone starts by Newton from the drawing, whose last
/// correction leaves its q a few ulps off the closed form's (and its pivot ratio, the LU's
/// at the start, as far). On one thread and on two. The crank-rockers
/// and the double-crank are the closed form of their own lengths on the asked (open)
/// circuit at every step.
#[test]
fn lanes_are_each_design_swept_alone_bit_for_bit() {
    let designs = designs();
    let s = setup(&designs);
    let request = Request { derivatives: 0, ..Request::default() };
    assert!(fit(&s.model, &request), "the four-bar's positions are the lanes'");
    for n_steps in [360, 48] {
        let t = times(n_steps);
        for threads in [1, 2] {
            let f = sweep_variants(
                &s.model,
                &s.variation,
                designs.len(),
                &s.deltas,
                &t,
                request,
                &s.outputs,
                &s.named,
                threads,
                &mut |_| true,
            );
            let mut failed = 0;
            let mut in_lanes = 0;
            for (i, d) in designs.iter().enumerate() {
                let (out, err) = alone(&s, i, &t, request);
                let k = out.n_done;
                let what = format!("design {i}, {n_steps} steps, {threads} threads");
                assert_eq!(f.n_done[i], k, "{what}");
                assert_eq!(f.errors[i].as_ref().map(|e| format!("{e:?}")), err, "{what}");
                assert_eq!(f.events[i], out.events.len(), "{what}: events");
                let (q, p) = (&f.q[i * n_steps..][..k], &f.points[i * n_steps * 4..][..k * 4]);
                let min = out.pivot_ratio[..k].iter().copied().fold(f64::INFINITY, f64::min);
                let same = bits(q) == bits(&out.q[..k])
                    && bits(p) == bits(&out.points[..k * 4])
                    && f.pivot_min[i].to_bits() == min.to_bits();
                if !same {
                    // a design the lanes took: its own start, then the scalar steps
                    in_lanes += 1;
                    let apart =
                        |x: &[f64], y: &[f64]| x.iter().zip(y).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                    let (dq, dp) = (apart(q, &out.q[..k]), apart(p, &out.points[..k * 4]));
                    eprintln!("{what}: in lanes, {dq:.2e} (angle), {dp:.2e} (points) from its sweep alone");
                    assert!(dq <= LANE_START && dp <= LANE_START, "{what}: {dq:e}, {dp:e}");
                    // the start's pivot ratio is Phi_q's LU with its pivots chosen at the
                    // start, the lanes' closed form or the sweep alone's Newton solution, a
                    // round-off apart (2.6e-16 apart, relative, at most)
                    let apart = (f.pivot_min[i] - min).abs() / min;
                    assert!(apart <= 1e-12, "{what}: pivot ratio {} against {min}", f.pivot_min[i]);
                }
                failed += err.is_some() as usize;
                if err.is_none() {
                    // the asked circuit (B left of A -> O4, as the closed form takes it):
                    // the coupler point from the closed form's coupler angle
                    let m = &d.m;
                    for (kk, tk) in t.iter().enumerate() {
                        let th2 = OMEGA * tk;
                        let ([th3, _], _, _) = four_bar_closed(m, th2, OMEGA, 0.0);
                        let want = [
                            m.r2 * th2.cos() + d.l5 * (th3 + d.g).cos(),
                            m.r2 * th2.sin() + d.l5 * (th3 + d.g).sin(),
                        ];
                        let got = &f.points[(i * n_steps + kk) * 4..][..2];
                        // the closed form's arccos next to the change point loses digits there
                        let tol = if i == 4 { 1e-9 } else { 1e-13 };
                        assert!(
                            (got[0] - want[0]).abs() < tol && (got[1] - want[1]).abs() < tol,
                            "{what}, step {kk}: {got:?} against {want:?}"
                        );
                    }
                }
            }
            assert_eq!(failed, 2, "only the two cranks that cannot turn stop");
            // at least the three crank-rockers and the double-crank of the first chunk
            eprintln!("{n_steps} steps, {threads} threads: {in_lanes} designs in lanes");
            assert!(in_lanes >= 4, "the designs the lanes take to the end: {in_lanes}");
        }
    }
}

/// The lanes themselves: four designs clear of their singular configurations take every
/// step in lanes, the same bits as their own sweeps; a lane whose design cannot turn
/// misses at a step at or before the one its own sweep stops at (the careful path's), the
/// rows before it its sweep's.
#[test]
fn each_lane_keeps_its_own_branch_and_first_missed_step() {
    let all = designs();
    // design 4 passes 1e-4 from its change point at half a turn: closer than the crank
    // moves it in a step, so the guard cannot show that step and hands it to the careful path
    // LANES designs from each set, taken in turn: crank-rockers and the double-crank; and
    // two of them with the crank that cannot turn and the design next to its change point
    for (set, missing) in [(&[0, 1, 2, 3, 7, 8, 9][..], &[][..]), (&[0, 5, 2, 4][..], &[5, 4][..])] {
        let picks: Vec<usize> = set.iter().copied().cycle().take(LANES).collect();
        let want_missed: Vec<bool> = picks.iter().map(|i| missing.contains(i)).collect();
        let chosen: Vec<Design> = picks
            .iter()
            .map(|&i| design(all[i].m.r1, all[i].m.r2, all[i].m.r3, all[i].m.r4, all[i].l5, all[i].g))
            .collect();
        let s = setup(&chosen);
        let t = times(360);
        let request = Request { derivatives: 0, ..Request::default() };
        let m = s.variation.params.len();
        let asked = asked_branches(&s.model, t[0]);
        let mut models = Vec::new();
        let mut data = Vec::new();
        let mut outs = Vec::new();
        for j in 0..LANES {
            let design = s.variation.model(&s.model, &s.deltas[j * m..(j + 1) * m]);
            let mut outputs = s.outputs.clone();
            for (slot, k) in outputs.points.iter_mut().zip(&s.named) {
                if let Some(k) = k {
                    slot.1 = design.points[*k].local;
                }
            }
            let mut d = Data::new(&design);
            let mut out = SweepOutput::with_outputs(&design, &t[..1], request, outputs);
            sweep_on(&design, &mut d, &t[..1], &mut out, 0, &mut |_| true, asked.as_ref()).unwrap();
            models.push(design);
            data.push(d);
            outs.push(out);
        }
        let points: Vec<_> = (0..2)
            .map(|i| (outs[0].outputs.points[i].0, std::array::from_fn(|j| outs[j].outputs.points[i].1)))
            .collect();
        let run = |turns: &mut Turns| {
            let mut q = vec![vec![f64::NAN; t.len()]; LANES];
            let mut p = vec![vec![f64::NAN; t.len() * 4]; LANES];
            let mut rows: Vec<LaneRows> = q
                .iter_mut()
                .zip(p.iter_mut())
                .map(|(q, p)| LaneRows { q, points: p, pivot_min: f64::INFINITY })
                .collect();
            let rows: &mut [LaneRows; LANES] = (&mut rows[..]).try_into().unwrap();
            let missed = sweep_lanes(
                std::array::from_fn(|j| &models[j]),
                std::array::from_fn(|j| &data[j]),
                &t,
                &s.outputs,
                &points,
                rows,
                turns,
                &|| false,
            )
            .expect("one plan shape");
            (missed, q, p)
        };
        // the crank's cos and sin: computed in the first run, read from the memo in a
        // second run of the same angles (every step but the first, whose base is each
        // design's start), the same bits
        let mut turns = Turns::default();
        let (missed, q, p) = run(&mut turns);
        assert_eq!(turns.hits, 0);
        let again = run(&mut turns);
        assert!(
            turns.hits >= missed.iter().map(|m| m.unwrap_or(t.len())).max().unwrap() - 2,
            "{}",
            turns.hits
        );
        assert_eq!(again.0, missed);
        for j in 0..LANES {
            assert_eq!(bits(&again.1[j]), bits(&q[j]));
            assert_eq!(bits(&again.2[j]), bits(&p[j]));
        }
        for j in 0..LANES {
            let (out, err) = alone(&s, j, &t, request);
            assert_eq!(missed[j].is_some(), want_missed[j], "lane {j}: {:?}", missed[j]);
            // the rows the lane took (step 0 is the design's own start)
            let took = missed[j].unwrap_or(t.len());
            assert!(
                took <= out.n_done.max(1) || err.is_none(),
                "lane {j} missed at {took}, its sweep stopped at {}",
                out.n_done
            );
            assert!(took <= out.n_done, "lane {j}");
            assert_eq!(bits(&q[j][1..took]), bits(&out.q[1..took]), "lane {j}: angle");
            assert_eq!(bits(&p[j][4..took * 4]), bits(&out.points[4..took * 4]), "lane {j}: points");
        }
    }
}

/// A cancelled batch stops its lanes at their next poll (every 4096 steps): each design
/// then reports its cancellation, none runs on to its last step.
#[test]
fn a_cancelled_batch_stops_its_lanes() {
    let designs = designs();
    // LANES designs that turn (the crank-rockers and the double-crank, in turn)
    let turning: Vec<Design> = [0, 1, 2, 3, 7, 8, 9]
        .iter()
        .cycle()
        .take(LANES)
        .map(|&i| {
            let d = &designs[i];
            design(d.m.r1, d.m.r2, d.m.r3, d.m.r4, d.l5, d.g)
        })
        .collect();
    let s = setup(&turning);
    let turn = std::f64::consts::TAU / OMEGA;
    // ten turns of 10,000 steps each (the lanes poll every 4096 steps), cancelled at the
    // first look: before the lanes start or while they run
    let t: Vec<f64> = (0..100_000).map(|k| 10.0 * turn * k as f64 / 100_000.0).collect();
    let request = Request { derivatives: 0, ..Request::default() };
    let f = sweep_variants(
        &s.model,
        &s.variation,
        LANES,
        &s.deltas,
        &t,
        request,
        &s.outputs,
        &s.named,
        1,
        &mut |_| false,
    );
    for i in 0..LANES {
        assert!(f.n_done[i] < t.len(), "design {i} ran on to the end");
        assert!(
            matches!(f.errors[i], Some(linkwork::SolveError::Cancelled { .. })),
            "design {i}: {:?}",
            f.errors[i]
        );
    }
}
