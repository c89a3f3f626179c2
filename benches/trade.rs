//! Benches of the trade and map outputs: a 100 × 80 heat map with contours (marching squares
//! on 7 900 quads, SVG text), and a trade assessment of 2 500 rows (the Pareto front is a
//! quadratic all-pairs check, so this is its cost at a 50 × 50 two-axis sweep).

use criterion::{criterion_group, criterion_main, Criterion};
use critspeed::plot::{heat_map_svg, HeatMap};
use critspeed::study::units::Dimension;
use critspeed::trade::{assess, Constraint, Objective, ResultKind, Row, Sense, Target, TradePlan};
use std::hint::black_box;

fn map() -> HeatMap {
    let (nx, ny) = (100, 80);
    let x: Vec<f64> = (0..nx)
        .map(|i| 100.0 * 30f64.powf(i as f64 / (nx - 1) as f64))
        .collect();
    let y: Vec<f64> = (0..ny)
        .map(|j| 0.05 + 0.35 * j as f64 / (ny - 1) as f64)
        .collect();
    let z = y
        .iter()
        .flat_map(|&c| x.iter().map(move |&k| Some(20.0 + 0.004 * k / c)))
        .collect();
    HeatMap {
        title: "bench".into(),
        x_label: "k (N/mm)".into(),
        y_label: "conicity (-)".into(),
        x,
        y,
        x_log: true,
        y_log: false,
        z,
        z_label: "V (m/s)".into(),
        threshold: Some((55.56, "V = 55.6 m/s".into())),
        above: None,
    }
}

fn trade() -> (TradePlan, Vec<Row>) {
    let key = "suspension.longitudinal_stiffness";
    let rows = (0..2500)
        .map(|i| {
            let k = 1e5 * (1.0 + (i % 50) as f64);
            let v = 30.0 + ((i * 7919) % 101) as f64;
            Row {
                id: i.to_string(),
                axes: vec![(key.into(), k)],
                results: [Some(v), None, Some(v)],
                status: "ok".into(),
                above: [false; 3],
                stable_up_to_m_s: None,
            }
        })
        .collect();
    let plan = TradePlan {
        objective: Objective {
            key: key.into(),
            sense: Sense::Minimize,
            dim: Dimension::Stiffness,
        },
        constraints: vec![Constraint {
            target: Target::Result(ResultKind::NonlinearCriticalSpeed),
            at_least: Some(61.1),
            at_most: None,
            text: String::new(),
        }],
        pareto: ResultKind::NonlinearCriticalSpeed,
        method: critspeed::trade::Method::Grid,
    };
    (plan, rows)
}

fn benches(c: &mut Criterion) {
    let h = map();
    c.bench_function("heat_map_100x80", |b| {
        b.iter(|| heat_map_svg(black_box(&h)))
    });
    let (plan, rows) = trade();
    c.bench_function("trade_assess_2500_rows", |b| {
        b.iter(|| assess(black_box(&plan), black_box(&rows)))
    });
}

criterion_group!(trade_benches, benches);
criterion_main!(trade_benches);
