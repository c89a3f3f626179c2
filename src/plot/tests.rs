//! Rendering tests; two of them also write example SVGs to the temp directory for viewing.

use super::*;

fn line(name: &str, points: Vec<(f64, f64)>, dashed: bool) -> Series {
    Series {
        name: name.into(),
        points,
        style: Style::Line { dashed },
    }
}

fn marker(at: f64, label: &str) -> Marker {
    Marker {
        at,
        label: label.into(),
    }
}

fn speeds() -> impl Iterator<Item = f64> + Clone {
    (0..=60).map(|i| 20.0 + 5.0 * f64::from(i))
}

/// Damping of the hunting mode vs speed, using every style.
fn example() -> Figure {
    let zeta = |v: f64| 0.12 * (1.0 - (v / 184.3).powi(2)) + 0.01 * (v / 60.0).sin();
    let mut nonlinear: Vec<_> = speeds().map(|v| (v, zeta(v))).collect();
    nonlinear[30].1 = f64::NAN;
    let sims = speeds().step_by(6).map(|v| (v, zeta(v) - 0.012)).collect();
    let measured: Vec<_> = speeds().step_by(4).map(|v| (v, zeta(v) + 0.015)).collect();
    let amplitude = measured.iter().map(|p| 2.0 + 0.03 * p.0).collect();
    Figure {
        title: "Hunting-mode damping vs speed".into(),
        x_label: "speed (m/s)".into(),
        y_label: "damping ratio ζ (-)".into(),
        series: vec![
            line("nonlinear model", nonlinear, false),
            line(
                "linearised model",
                speeds().map(|v| (v, 0.12 - 0.0007 * v)).collect(),
                true,
            ),
            Series {
                name: "time-domain simulation".into(),
                points: sims,
                style: Style::Points,
            },
            Series {
                name: "measured".into(),
                points: measured,
                style: Style::PointsColoured {
                    values: amplitude,
                    label: "amplitude (mm)".into(),
                },
            },
        ],
        vlines: vec![
            marker(184.3, "V_L = 184.3 m/s"),
            marker(171.4, "V_nl = 171.4 m/s"),
        ],
        hlines: vec![marker(0.0, "ζ = 0")],
        ..Figure::default()
    }
}

fn geometry_panels() -> Vec<Figure> {
    let ys: Vec<f64> = (-40..=40).map(|i| f64::from(i) * 2.5e-4).collect();
    let panel = |title: &str, y_label: &str, series: Vec<Series>| Figure {
        title: title.into(),
        x_label: "lateral displacement y (m)".into(),
        y_label: y_label.into(),
        series,
        ..Figure::default()
    };
    let curve = |name: &str, f: &dyn Fn(f64) -> f64, dashed| {
        line(name, ys.iter().map(|&y| (y, f(y))).collect(), dashed)
    };
    vec![
        panel(
            "Rolling-radius difference",
            "Δr (m)",
            vec![curve("Δr", &|y| 0.15 * y + 40.0 * y.powi(3), false)],
        ),
        panel(
            "Contact angles",
            "contact angle (rad)",
            vec![
                curve(
                    "left",
                    &|y| 0.05 + 8.0 * y + 2000.0 * y.powi(2).max(0.0) * y.signum().max(0.0),
                    false,
                ),
                curve("right", &|y| 0.05 - 8.0 * y, true),
            ],
        ),
        panel(
            "Roll angle",
            "roll angle (rad)",
            vec![curve("", &|y| 2.0e-3 * y + 0.4 * y.powi(3), false)],
        ),
        panel(
            "Hertz semi-axes",
            "semi-axis (m)",
            vec![
                curve(
                    "a (longitudinal)",
                    &|y| 0.0071 + 0.02 * y * y.signum(),
                    false,
                ),
                curve("b (lateral)", &|y| 0.0048 - 0.01 * y.abs(), true),
            ],
        ),
    ]
}

#[test]
fn renders_every_style_with_markers() {
    let svg = render_svg(&example(), 900, 560).expect("render");
    std::fs::write(
        std::env::temp_dir().join("critspeed_plot_example.svg"),
        &svg,
    )
    .expect("write");
    assert!(svg.starts_with("<svg width=\"900\" height=\"560\" viewBox=\"0 0 3600 2240\""));
    assert!(svg.trim_end().ends_with("</svg>"));
    for text in [
        "Hunting-mode damping vs speed",
        "nonlinear model",
        "linearised model",
    ] {
        assert!(svg.contains(text), "missing {text}");
    }
    for text in [
        "time-domain simulation",
        "measured",
        "V_L = 184.3 m/s",
        "ζ = 0",
        "amplitude (mm)",
    ] {
        assert!(svg.contains(text), "missing {text}");
    }
    assert_eq!(svg.matches("<svg").count(), svg.matches("</svg>").count());
    // Dashed lines are emitted as many short polylines in the series colour
    // (plotters' SVG backend has no stroke-dasharray).
    let vermillion = svg.matches("stroke=\"#D55E00\"").count();
    assert!(
        vermillion > 20,
        "dashed series has {vermillion} dash segments"
    );
    let blue = svg
        .matches("polyline fill=\"none\" opacity=\"1\" stroke=\"#0072B2\"")
        .count();
    assert_eq!(
        blue, 3,
        "NaN splits the solid line into two runs, plus the legend swatch"
    );
}

#[test]
fn grid_of_four_panels() {
    let svg = render_grid(&geometry_panels(), 2, 1200, 820).expect("render grid");
    std::fs::write(std::env::temp_dir().join("critspeed_plot_grid.svg"), &svg).expect("write");
    for t in [
        "Rolling-radius difference",
        "Contact angles",
        "Roll angle",
        "Hertz semi-axes",
    ] {
        assert!(svg.contains(t), "missing {t}");
    }
    assert!(svg.contains("[×10⁻³]"), "small magnitudes are factored out");
    assert!(render_grid(&geometry_panels(), 0, 1200, 820).is_ok());
    assert!(
        render_grid(&geometry_panels(), 9, 600, 400).is_err(),
        "panels too small"
    );
}

#[test]
fn empty_and_non_finite_errors() {
    let empty = Figure {
        title: "nothing".into(),
        ..Figure::default()
    };
    assert!(
        matches!(render_svg(&empty, 640, 400), Err(PlotError::Empty { title }) if title == "nothing")
    );
    let mut no_points = empty.clone();
    no_points.series.push(line("a", vec![], false));
    assert!(matches!(
        render_svg(&no_points, 640, 400),
        Err(PlotError::Empty { .. })
    ));
    assert!(matches!(
        render_grid(&[], 2, 640, 400),
        Err(PlotError::Empty { .. })
    ));
    let mut nan = empty.clone();
    nan.series
        .push(line("ok", vec![(0.0, 1.0), (1.0, 2.0)], false));
    nan.series.push(line(
        "bad",
        vec![(f64::NAN, 1.0), (1.0, f64::INFINITY)],
        false,
    ));
    let err = render_svg(&nan, 640, 400).unwrap_err();
    assert!(
        matches!(&err, PlotError::NonFinite { series, .. } if series == "bad"),
        "{err}"
    );
    assert!(matches!(
        render_svg(&example(), 10, 10),
        Err(PlotError::Backend(_))
    ));
}

#[test]
fn nan_points_leave_gaps() {
    let pts = vec![
        (0.0, 0.0),
        (1.0, 1.0),
        (2.0, f64::NAN),
        (3.0, 1.0),
        (4.0, 0.0),
        (f64::INFINITY, 2.0),
    ];
    let fig = Figure {
        series: vec![line("gappy", pts, false)],
        ..Figure::default()
    };
    let svg = render_svg(&fig, 640, 400).expect("render");
    assert_eq!(
        svg.matches("stroke=\"#0072B2\"").count(),
        3,
        "two runs + legend swatch"
    );
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
}

#[test]
fn degenerate_and_odd_ranges_do_not_panic() {
    let flat = Figure {
        series: vec![line(
            "flat",
            vec![(1.0, 5.0), (2.0, 5.0), (3.0, 5.0)],
            false,
        )],
        ..Figure::default()
    };
    assert!(render_svg(&flat, 640, 400).expect("flat").contains("5.0"));
    let single = Figure {
        series: vec![Series {
            name: String::new(),
            points: vec![(0.0, 0.0)],
            style: Style::Points,
        }],
        ..Figure::default()
    };
    assert!(render_svg(&single, 640, 400).is_ok());
    let mut odd = example();
    odd.x_range = Some((f64::NAN, 3.0));
    odd.y_range = Some((1.0, -1.0));
    odd.vlines.push(marker(f64::INFINITY, "never"));
    odd.series[3].style = Style::PointsColoured {
        values: vec![f64::NAN],
        label: "v".into(),
    };
    let svg = render_svg(&odd, 640, 400).expect("odd ranges");
    assert!(!svg.contains("never"));
    let mut escaped = flat.clone();
    escaped.title = "a < b & \"c\"".into();
    let svg = render_svg(&escaped, 640, 400).expect("escaping");
    assert!(svg.contains("a &lt; b &amp; &quot;c&quot;"));
    let huge = Figure {
        series: vec![line(
            "",
            vec![(-f64::MAX, f64::MIN_POSITIVE), (f64::MAX, 1e300)],
            false,
        )],
        ..Figure::default()
    };
    assert!(render_svg(&huge, 640, 400).is_ok());
}

/// x position (SVG units) of the text element whose content is exactly `label`.
fn text_x(svg: &str, label: &str) -> Option<f64> {
    let lines: Vec<&str> = svg.lines().collect();
    lines.windows(2).find_map(|w| {
        let x = w[0].strip_prefix("<text x=\"")?.split('"').next()?;
        (w[1].trim() == label).then(|| x.parse().ok())?
    })
}

fn text_y(svg: &str, label: &str) -> Option<f64> {
    let lines: Vec<&str> = svg.lines().collect();
    lines.windows(2).find_map(|w| {
        let y = w[0].split(" y=\"").nth(1)?.split('"').next()?;
        (w[1].trim() == label).then(|| y.parse().ok())?
    })
}

#[test]
fn log_x_axis_places_ticks_by_their_logarithm() {
    // 1e5 … 3e6 on a log axis: ticks 1e5, 2e5, 5e5, 1e6, 2e6; the gap 1e5 → 2e5 is log10(2)
    // of the decade 1e5 → 1e6. A point at x = 0 cannot be drawn and is skipped.
    let mut pts: Vec<(f64, f64)> = (0..25)
        .map(|i| {
            let k = 1e5 * 30f64.powf(f64::from(i) / 24.0);
            (k, 40.0 + 10.0 * (k / 1e5).ln())
        })
        .collect();
    pts.push((0.0, 50.0));
    let fig = Figure {
        title: "log x".into(),
        x_label: "stiffness (N/m)".into(),
        y_label: "speed (m/s)".into(),
        series: vec![line("V", pts, false)],
        x_log: true,
        ..Figure::default()
    };
    let svg = render_svg(&fig, 1000, 640).expect("renders");
    let at = |l: &str| text_x(&svg, l).unwrap_or_else(|| panic!("tick {l} in the SVG"));
    let (a, b, c) = (at("1e5"), at("2e5"), at("1e6"));
    let ratio = (b - a) / (c - a);
    assert!((ratio - 2f64.log10()).abs() < 2e-3, "{ratio}");
    assert!(at("5e5") > b && at("2e6") > c);
}

/// The plot area's right edge (SVG units): the end of the horizontal grid lines.
fn plot_right(svg: &str) -> f64 {
    svg.lines()
        .filter(|l| l.starts_with("<line") && l.contains("stroke=\"#E3E3E3\""))
        .filter_map(|l| l.split("x2=\"").nth(1)?.split('"').next()?.parse().ok())
        .fold(f64::NEG_INFINITY, f64::max)
}

/// A figure titled `title` over the unit square, axes "x (m)" and "y (m)".
fn unit_square(title: &str, series: Vec<Series>) -> Figure {
    Figure {
        title: title.into(),
        x_label: "x (m)".into(),
        y_label: "y (m)".into(),
        series,
        x_range: Some((0.0, 1.0)),
        y_range: Some((0.0, 1.0)),
        ..Figure::default()
    }
}

#[test]
fn the_legend_goes_beside_the_plot_only_when_every_place_inside_covers_data() {
    let figure = |series: Vec<Series>| unit_square("legend", series);
    // a line in the lower left only: the legend stays inside, in the free upper right
    let corner = figure(vec![line(
        "corner",
        vec![(0.0, 0.0), (0.2, 0.1), (0.3, 0.3)],
        false,
    )]);
    let svg = render_svg(&corner, 1000, 640).expect("renders");
    let (x, right) = (text_x(&svg, "corner").expect("legend"), plot_right(&svg));
    assert!(x < right, "legend at {x}, plot ends at {right}");
    // points everywhere: no place inside is free, so the legend is right of the plot
    let grid: Vec<(f64, f64)> = (0..=40)
        .flat_map(|i| (0..=40).map(move |j| (f64::from(i) / 40.0, f64::from(j) / 40.0)))
        .collect();
    let full = figure(vec![Series {
        name: "everywhere".into(),
        points: grid,
        style: Style::Points,
    }]);
    let svg = render_svg(&full, 1000, 640).expect("renders");
    let (x, right) = (
        text_x(&svg, "everywhere").expect("legend"),
        plot_right(&svg),
    );
    assert!(x > right, "legend at {x}, plot ends at {right}");
}

/// Where neither a place inside nor beside will do (data everywhere, names so long that a
/// legend beside would leave the plot less than half the width), the legend goes below the
/// plot in columns, each as wide as its widest entry, and hides nothing.
#[test]
fn the_legend_goes_below_the_plot_in_columns_when_beside_would_squeeze_it() {
    let grid: Vec<(f64, f64)> = (0..=40)
        .flat_map(|i| (0..=40).map(move |j| (f64::from(i) / 40.0, f64::from(j) / 40.0)))
        .collect();
    let long =
        "a series whose name is long enough to take more than half of the width of the figure";
    let mut series = vec![Series {
        name: long.into(),
        points: grid,
        style: Style::Points,
    }];
    for k in 0..5 {
        series.push(line(
            &format!("short {k}"),
            vec![(0.0, 0.0), (1.0, 1.0)],
            false,
        ));
    }
    let f = unit_square("legend below", series);
    let svg = render_svg(&f, 1000, 640).expect("renders");
    assert!(
        super::legend_clashes(&svg).is_empty(),
        "{:?}",
        super::legend_clashes(&svg)
    );
    assert_eq!(super::legend_count(&svg), 1);
    // below the plot: under the x-axis title
    let axis_title_y = text_y(&svg, "x (m)").expect("x title");
    let long_y = text_y(&svg, long).expect("legend entry");
    assert!(long_y > axis_title_y, "{long_y} vs {axis_title_y}");
    // two columns: the long name's column, then the short ones beside it
    let (x_long, x_short) = (
        text_x(&svg, long).expect("entry"),
        text_x(&svg, "short 4").expect("entry"),
    );
    assert!(x_short > x_long, "{x_short} {x_long}");
}
