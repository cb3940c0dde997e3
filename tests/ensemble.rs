//! Ensembles: a run's inputs depend only on the ensemble and its index, so every way of
//! running them (all cores, one thread, chunks) gives one table; grids are a Cartesian
//! product in order; uniform draws stay in their range; failed runs keep their error.

use filippov::runtime::ensemble::{Draw, Ensemble, Table};
use filippov::scenes::RestingArm;

fn arm(fc: Draw, e: Draw, samples: usize, seed: u64) -> Ensemble<RestingArm, 2> {
    let f = Draw::Fixed;
    Ensemble::new(
        vec![f(1.0), f(1.0), f(0.5), f(0.7), fc, f(-1.0), e],
        vec![
            f(0.2),
            Draw::Uniform {
                low: -1.0,
                high: 1.0,
            },
        ],
        vec![f(0.0), f(0.0)],
        samples,
        seed,
        2.0,
    )
    .expect("a valid ensemble")
}

/// Friction and restitution drawn uniformly, 120 runs.
fn random_arm(seed: u64) -> Ensemble<RestingArm, 2> {
    arm(
        Draw::Uniform {
            low: 0.5,
            high: 20.0,
        },
        Draw::Uniform {
            low: 0.0,
            high: 0.9,
        },
        120,
        seed,
    )
}

fn bits(t: &Table) -> (Vec<u64>, Vec<u64>) {
    (
        t.inputs.iter().map(|x| x.to_bits()).collect(),
        t.outputs.iter().map(|x| x.to_bits()).collect(),
    )
}

#[test]
fn every_way_of_running_gives_one_table() {
    let ens = random_arm(11);
    let all = ens.table(0..ens.len(), None, false);
    let one = ens.table(0..ens.len(), Some(1), false);
    assert_eq!(bits(&all), bits(&one));
    assert_eq!(all.errors, one.errors);
    // Chunks, joined, are the whole.
    let mut joined = Vec::new();
    for start in (0..ens.len()).step_by(37) {
        let part = ens.table(start..(start + 37).min(ens.len()), Some(2), false);
        joined.extend(part.outputs);
    }
    assert_eq!(
        joined.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        bits(&all).1
    );
    // The draws: inside their ranges, and not all alike.
    let fc: Vec<f64> = (0..all.runs.len()).map(|k| all.input_row(k)[4]).collect();
    assert!(fc.iter().all(|x| (0.5..20.0).contains(x)));
    assert!(fc.windows(2).any(|w| w[0] != w[1]));
    // Another seed draws otherwise; the same seed again the same.
    let again = random_arm(11);
    assert_eq!(again.inputs(57), ens.inputs(57));
    let other = random_arm(12);
    assert_ne!(other.inputs(57), ens.inputs(57));
    // Physics: no run passes the rigid stop at −1.
    for k in 0..all.runs.len() {
        if all.errors[k].is_none() {
            assert!(all.output_row(k)[0] >= -1.0, "run {k} passed the stop");
        }
    }
}

#[test]
fn grids_are_a_product_in_declaration_order() {
    let ens = arm(
        Draw::Grid(vec![1.0, 5.0]),
        Draw::Grid(vec![0.0, 0.3, 0.6]),
        2,
        0,
    );
    assert_eq!(ens.len(), 12);
    let fc: Vec<f64> = (0..12).map(|i| ens.inputs(i)[4]).collect();
    let e: Vec<f64> = (0..12).map(|i| ens.inputs(i)[6]).collect();
    assert_eq!(
        fc,
        [1.0; 6]
            .iter()
            .chain(&[5.0; 6])
            .copied()
            .collect::<Vec<_>>()
    );
    assert_eq!(e, [0.0, 0.0, 0.3, 0.3, 0.6, 0.6].repeat(2));
}

#[test]
fn failed_runs_keep_their_error_and_bad_ensembles_are_refused() {
    let ens = arm(
        Draw::Uniform {
            low: -5.0,
            high: 5.0,
        },
        Draw::Fixed(0.5),
        60,
        5,
    );
    let t = ens.table(0..ens.len(), None, false);
    assert_eq!(t.runs, (0..60).collect::<Vec<_>>());
    for k in 0..60 {
        let negative = t.input_row(k)[4] < 0.0;
        match &t.errors[k] {
            Some(e) => {
                assert!(negative && e.kind == "InvalidParameters" && e.message.contains("fc"));
                assert!(t.output_row(k).iter().all(|x| x.is_nan()));
            }
            None => assert!(!negative && t.output_row(k).iter().all(|x| x.is_finite())),
        }
    }
    assert!(t.errors.iter().any(Option::is_some) && t.errors.iter().any(Option::is_none));
    let f = Draw::Fixed;
    let wrong =
        Ensemble::<RestingArm, 2>::new(vec![f(1.0)], vec![f(0.0); 2], vec![f(0.0); 2], 1, 0, 1.0);
    assert!(wrong.unwrap_err().contains("m1, l1, m2, l2, fc, lim, e"));
    let empty = Ensemble::<RestingArm, 2>::new(
        vec![
            f(1.0),
            f(1.0),
            f(0.5),
            f(0.7),
            Draw::Grid(vec![]),
            f(-1.0),
            f(0.5),
        ],
        vec![f(0.0); 2],
        vec![f(0.0); 2],
        1,
        0,
        1.0,
    );
    assert!(empty.unwrap_err().contains("fc: a grid needs"));
}
