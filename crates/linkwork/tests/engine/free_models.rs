//! Models compiled with free coordinates (`Options::free`): they compile and report their
//! degrees of freedom; every kinematic entry point refuses them by name; without the
//! option, the row-count error says how to simulate them.

use linkwork::{Data, Description, Model, Options, Request, SolveError, SweepOutput};

fn pendulum() -> Description {
    Description::from_json(
        r#"{"name": "pendulum", "gravity": [0, -9.81],
            "bodies": [{"name": "bar", "x": 1.0, "y": 0.0, "mass": 1.0}],
            "joints": [{"type": "revolute", "name": "O", "body_a": "ground", "body_b": "bar", "at": [0, 0]}]}"#,
    )
    .unwrap()
}

#[test]
fn without_the_option_the_row_count_error_points_to_simulate() {
    let e = Model::new(pendulum()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("1 degree(s) of freedom") && msg.contains("compile(free=True)"), "{msg}");
}

#[test]
fn a_free_model_compiles_and_every_kinematic_solve_refuses_it() {
    let model = Model::with_options(pendulum(), Options { free: true, ..Options::default() }).unwrap();
    assert_eq!((model.dof(), model.n_rows, model.n_coords), (1, 2, 3));
    assert_eq!(model.plan.as_ref().err().map(String::as_str), Some("free model"));
    let mut data = Data::new(&model);
    let times = [0.0, 0.1];
    let mut out = SweepOutput::with_request(&model, &times, Request::default());
    let errors = [
        linkwork::sweep(&model, &mut data, &times, &mut out, 0, &mut |_| true).unwrap_err(),
        linkwork::solve(&model, &mut data, 0.0).unwrap_err(),
        linkwork::solve_position(&model, &mut data, 0.0, 0, true).unwrap_err(),
        linkwork::sweep_batch(&[&model], &times, Request::default(), 1, &mut |_| true)[0].1.clone().unwrap(),
    ];
    for e in errors {
        assert_eq!(e, SolveError::Free { dof: 1 });
        assert!(e.to_string().contains("this model has 1 free coordinate(s): simulate it (model.simulate)"));
    }
    // a model whose rows match its coordinates is not changed by the option
    let square = Model::with_options(
        linkwork::Description::from_json(
            r#"{"bodies": [{"name": "crank", "x": 0, "y": 0}],
                "joints": [{"type": "revolute", "name": "O", "body_a": "ground", "body_b": "crank", "at": [0, 0]}],
                "drivers": [{"type": "angle", "name": "d", "body": "crank", "law": {"type": "linear", "value": 0, "rate": 1}}]}"#,
        )
        .unwrap(),
        Options { free: true, ..Options::default() },
    )
    .unwrap();
    assert_eq!(square.dof(), 0);
    assert!(linkwork::solve(&square, &mut Data::new(&square), 0.3).is_ok());
}
