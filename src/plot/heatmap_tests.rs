//! Tests of the heat map and trade plot: validation, labels, failed cells.

use super::heatmap::contour_levels;
use super::*;

fn map(nx: usize, ny: usize, f: impl Fn(f64, f64) -> Option<f64>) -> HeatMap {
    let x: Vec<f64> = (0..nx)
        .map(|i| 100.0 * 30f64.powf(i as f64 / (nx - 1) as f64))
        .collect();
    let y: Vec<f64> = (0..ny)
        .map(|j| 0.1 + 0.4 * j as f64 / (ny - 1) as f64)
        .collect();
    let z = y
        .iter()
        .flat_map(|&b| x.iter().map(move |&a| (a, b)))
        .map(|(a, b)| f(a, b))
        .collect();
    HeatMap {
        title: "critical speed map".into(),
        x_label: "longitudinal stiffness (N/mm)".into(),
        y_label: "conicity (-)".into(),
        x,
        y,
        x_log: true,
        y_log: false,
        z,
        z_label: "critical speed (m/s)".into(),
        threshold: Some((55.56, "stable above / unstable below: V = 55.6 m/s".into())),
        above: None,
    }
}

fn speed(k: f64, c: f64) -> Option<f64> {
    Some(20.0 + 0.04 * k / (c * 10.0))
}

#[test]
fn svg_has_labels_colour_bar_and_threshold() {
    let h = map(25, 15, speed);
    let svg = heat_map_svg(&h).expect("valid map");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    for text in [
        "critical speed map",
        "longitudinal stiffness (N/mm)",
        "conicity (-)",
        "critical speed (m/s)",
        "stable above / unstable below: V = 55.6 m/s",
    ] {
        assert!(svg.contains(text), "missing {text}");
    }
    assert!(!svg.contains("no value ("), "no failed point in this map");
    // contour labels are the nice levels
    let zs: Vec<f64> = h.z.iter().flatten().copied().collect();
    let (lo, hi) = zs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let levels = contour_levels(lo, hi);
    assert!((5..=9).contains(&levels.len()), "{levels:?}");
    for l in &levels {
        assert!(svg.contains(&format!(">{}</text>", scale::format_value(*l))));
    }
}

#[test]
fn failed_points_are_hatched_and_listed() {
    let h = map(10, 8, |k, c| {
        if k > 500.0 && c > 0.3 {
            None
        } else {
            speed(k, c)
        }
    });
    let svg = heat_map_svg(&h).expect("valid map");
    let failed = h.z.iter().filter(|z| z.is_none()).count();
    assert!(failed > 0);
    assert!(svg.contains(&format!("no value ({failed})")));
    assert_eq!(svg.matches("fill=\"url(#failed)\"/>").count(), failed);
}

#[test]
fn invalid_maps_are_errors_not_panics() {
    let good = map(5, 4, speed);
    let mut h = good.clone();
    h.x.truncate(1);
    assert!(matches!(heat_map_svg(&h), Err(PlotError::Invalid { .. })));
    let mut h = good.clone();
    h.y[2] = h.y[1];
    let e = heat_map_svg(&h).expect_err("not increasing");
    assert!(e.to_string().contains("increase strictly"), "{e}");
    let mut h = good.clone();
    h.x[0] = -1.0;
    assert!(heat_map_svg(&h)
        .expect_err("log")
        .to_string()
        .contains("positive"));
    let mut h = good.clone();
    h.z.pop();
    assert!(heat_map_svg(&h)
        .expect_err("len")
        .to_string()
        .contains("z has 19 values"));
    let mut h = good.clone();
    h.y[0] = f64::NAN;
    assert!(heat_map_svg(&h).is_err());
    let mut h = good.clone();
    h.z.iter_mut().for_each(|z| *z = None);
    assert!(matches!(heat_map_svg(&h), Err(PlotError::Empty { .. })));
    let mut h = good;
    h.threshold = Some((f64::INFINITY, String::new()));
    assert!(heat_map_svg(&h).is_err());
}

#[test]
fn contour_levels_are_five_to_nine_nice_values_inside() {
    for (lo, hi) in [
        (17.22, 190.6),
        (0.0, 1.0),
        (20.8, 140.0),
        (-3.0, 1e-3),
        (1e5, 3e6),
        (0.3, 0.31),
    ] {
        let l = contour_levels(lo, hi);
        assert!((5..=9).contains(&l.len()), "{lo}..{hi}: {l:?}");
        assert!(l.iter().all(|v| *v > lo && *v < hi), "{l:?}");
        let step = l[1] - l[0];
        let m = step / 10f64.powf(step.log10().floor());
        assert!(
            [1.0, 2.0, 2.5, 5.0].iter().any(|n| (m - n).abs() < 1e-9),
            "step {step}"
        );
    }
    assert!(contour_levels(1.0, 1.0).is_empty());
}

#[test]
fn constant_map_renders() {
    let h = map(3, 3, |_, _| Some(7.0));
    assert!(heat_map_svg(&h).is_ok());
}

#[test]
fn trade_plot_validates_and_labels() {
    let pts = |x: f64, y: Option<f64>, f: bool| TradePoint {
        x,
        y,
        above: false,
        feasible: f,
        pareto: f,
        best: false,
    };
    let mut p = TradePlot {
        title: "trade".into(),
        x_label: "stiffness (N/mm)".into(),
        y_label: "speed (m/s)".into(),
        x_log: true,
        points: vec![pts(100.0, Some(50.0), false), pts(300.0, Some(70.0), true)],
        constraint: Some((61.1, "V ≥ 1.1 × 55.6 m/s".into())),
    };
    p.points.push(pts(1000.0, None, false));
    p.points[1].best = true;
    let svg = trade_svg(&p).expect("valid");
    for t in [
        "V ≥ 1.1 × 55.6 m/s",
        "best design",
        "no result (1)",
        "infeasible (1)",
    ] {
        assert!(svg.contains(t), "missing {t}");
    }
    p.points[0].x = 0.0;
    assert!(matches!(trade_svg(&p), Err(PlotError::Invalid { .. })));
    p.points.clear();
    assert!(matches!(trade_svg(&p), Err(PlotError::Empty { .. })));
}

#[test]
#[ignore = "writes sample SVGs to the temp dir for looking at"]
fn write_samples() {
    let h = map(25, 15, |k, c| {
        if k > 1500.0 && c > 0.38 && c < 0.45 {
            None
        } else {
            speed(k, c)
        }
    });
    let dir = std::env::temp_dir();
    std::fs::write(dir.join("heatmap.svg"), heat_map_svg(&h).expect("ok")).expect("write");
}

/// `speed` with cells above 100 m/s only known to exceed 100 (no onset in range), and the
/// soft, steep corner failed.
fn map_with_above() -> HeatMap {
    let mut h = map(10, 8, |k, c| {
        if k < 200.0 && c > 0.4 {
            None
        } else {
            speed(k, c)
        }
    });
    let cells: Vec<bool> = h.z.iter().map(|z| z.is_some_and(|v| v > 100.0)).collect();
    for (z, up) in h.z.iter_mut().zip(&cells) {
        if *up {
            *z = None;
        }
    }
    h.above = Some(AboveRange {
        cells,
        bound: 100.0,
        label: "> 100 m/s (no onset in range)".into(),
    });
    h
}

#[test]
fn above_range_cells_are_filled_not_hatched() {
    let h = map_with_above();
    let above = h
        .above
        .as_ref()
        .expect("set")
        .cells
        .iter()
        .filter(|a| **a)
        .count();
    let failed = h.z.iter().filter(|z| z.is_none()).count() - above;
    assert!(above > 0 && failed > 0, "{above} above, {failed} failed");
    let svg = heat_map_svg(&h).expect("valid map");
    // cells carry no stroke; the legend and colour-bar boxes do
    let cell = |fill: &str| svg.matches(&format!("fill=\"{fill}\"/>")).count();
    assert_eq!(cell("url(#failed)"), failed);
    assert_eq!(cell(ABOVE_FILL), above);
    assert!(svg.contains(&format!("no value ({failed})")));
    assert!(
        svg.contains(&format!("&gt; 100 m/s ({above})")),
        "legend entry"
    );
    assert!(svg.contains("(no onset in range)"));
}

#[test]
fn threshold_reaches_above_range_cells_only_below_their_bound() {
    // 40 m/s everywhere except the right half, which is above range (> 250 m/s)
    let mut h = map(6, 4, |_, _| Some(40.0));
    let cells: Vec<bool> = (0..h.z.len()).map(|k| k % 6 >= 3).collect();
    for (z, up) in h.z.iter_mut().zip(&cells) {
        if *up {
            *z = None;
        }
    }
    h.above = Some(AboveRange {
        cells,
        bound: 250.0,
        label: "> 250 m/s (no onset in range)".into(),
    });
    // 55.56 <= 250: the boundary between 40 and > 250 is known to lie between the columns
    let svg = heat_map_svg(&h).expect("map");
    assert!(!svg.contains("not reached on this map"));
    // 300 > 250: unknown whether the above cells reach it, so no line is drawn
    h.threshold = Some((300.0, "V = 300 m/s".into()));
    let svg = heat_map_svg(&h).expect("map");
    assert!(svg.contains("not reached on this map"));
}
