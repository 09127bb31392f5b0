//! The tests of `signorini_plot` that were unit tests in src/lib.rs (the
//! library is not compiled a second time as a test harness).

use signorini_plot::*;

#[test]
fn category_maps_draw_one_rectangle_per_run_of_equal_cells() {
    let c = Chart { title: "basins", x_label: "x", y_label: "v", scale: Scale::Linear, size: (600, 400) };
    let cats = [Category { name: "zero".into(), color: Some((1, 2, 3)) }, Category { name: "one".into(), color: Some((4, 5, 6)) }];
    // Row 0: 0 0 1 (two runs), row 1: 1 1 1 (one run), row 2: none, 0, none (one run).
    let cells = vec![vec![Some(0), Some(0), Some(1)], vec![Some(1); 3], vec![None, Some(0), None]];
    let svg = category_map(&c, (0.0, 1.0), (-1.0, 1.0), &cells, &cats).unwrap();
    let fill = |rgb: &str| svg.matches(&format!("fill=\"{rgb}\"")).count();
    // Each colour: its runs on the map and one legend swatch.
    assert_eq!((fill("#010203"), fill("#040506")), (2 + 1, 2 + 1), "{svg}");
    assert!(svg.contains("zero") && svg.contains("one") && svg.contains("basins"));
    assert!(category_map(&c, (0.0, 1.0), (0.0, 1.0), &[], &cats).is_err());
}

#[test]
fn stacked_panels_sit_one_under_the_other() {
    let a = "<svg width=\"100\" height=\"50\" viewBox=\"0 0 100 50\" xmlns=\"http://www.w3.org/2000/svg\">\n<text>first</text>\n</svg>\n".to_string();
    let b = "<svg width=\"80\" height=\"30\" viewBox=\"0 0 80 30\" xmlns=\"http://www.w3.org/2000/svg\">\n<text>second</text>\n</svg>\n".to_string();
    let svg = stack_vertically(&[a, b]).unwrap();
    assert!(svg.starts_with("<svg width=\"100\" height=\"80\" viewBox=\"0 0 100 80\""), "{svg}");
    let (first, second) = (svg.find("<svg x=\"0\" y=\"0\" width=\"100\"").unwrap(), svg.find("<svg x=\"0\" y=\"50\" width=\"80\"").unwrap());
    assert!(first < svg.find("first").unwrap() && svg.find("first").unwrap() < second && second < svg.find("second").unwrap());
    assert_eq!(svg.matches("</svg>").count(), 3);
    assert!(stack_vertically(&["<g/>".to_string()]).is_err());
}

#[test]
fn renders_svg_with_legend_and_skips_bad_points() {
    let s = vec![
        Series { label: "numerical".into(), points: vec![(0.0, 0.5), (1.0, f64::NAN), (2.0, -0.1)], reference: false, style: Style::default() },
        Series { label: "exact".into(), points: vec![(0.0, 0.5), (2.0, 0.0)], reference: true, style: Style::default() },
    ];
    let c = Chart { title: "u(0,t)", x_label: "t", y_label: "u", scale: Scale::Linear, size: (640, 400) };
    let svg = line_chart(&c, &s).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("numerical") && svg.contains("exact") && svg.contains("u(0,t)"));
    let log = Chart { scale: Scale::LogLog, ..c };
    let curve = Series { label: "error".into(), points: vec![(0.1, 1e-2), (0.05, 5e-3), (0.0, 1.0)], reference: false, style: Style::default() };
    assert!(line_chart(&log, &[curve]).unwrap().contains("error"));
    // Every point invalid on log axes: an error, not a panic.
    assert!(line_chart(&log, &[Series { label: "x".into(), points: vec![(0.0, -1.0)], reference: false, style: Style::default() }]).is_err());
}

#[test]
fn bad_input_is_a_typed_error_naming_the_chart() {
    let series = |points: Vec<(f64, f64)>| vec![Series { label: "x".into(), points, reference: false, style: Style::default() }];
    let lin = Chart { title: "lin", x_label: "t", y_label: "u", scale: Scale::Linear, size: (300, 200) };
    let log = Chart { title: "log", scale: Scale::LogLog, ..lin };
    let nothing = |r: Result<String, PlotError>, want: &str| match r {
        Err(PlotError::NothingToPlot { chart }) => assert_eq!(chart, want),
        other => panic!("{want}: expected NothingToPlot, got {other:?}"),
    };
    // No series, empty series, only NaN / ±∞ coordinates: nothing to plot, on any chart.
    nothing(line_chart(&lin, &[]), "lin");
    nothing(line_chart(&lin, &series(vec![])), "lin");
    nothing(line_chart(&lin, &series(vec![(f64::NAN, 1.0), (1.0, f64::INFINITY), (f64::NEG_INFINITY, 0.0)])), "lin");
    nothing(scatter(&lin, &series(vec![(1.0, f64::NAN)]), 1), "lin");
    // Log axes: a finite point at 0 or below cannot be drawn either;
    // the same points are drawable on linear axes.
    nothing(line_chart(&log, &series(vec![(0.0, 1.0), (1.0, -1.0), (-2.0, 3.0)])), "log");
    assert!(line_chart(&lin, &series(vec![(0.0, 1.0), (1.0, -1.0), (-2.0, 3.0)])).is_ok());
    // Panels that are not SVG documents with a pixel size: which panel, and why.
    let ok = line_chart(&lin, &series(vec![(0.0, 1.0), (1.0, 2.0)])).unwrap();
    for (bad, problem) in [("no svg here", PanelProblem::NoSvgElement), ("<svg width=\"10\"", PanelProblem::UnclosedTag), ("<svg width=\"10em\" height=\"5\">", PanelProblem::NoPixelSize)] {
        match stack_vertically(&[ok.clone(), bad.to_string()]) {
            Err(PlotError::Panel { panel: 1, problem: p }) => assert_eq!(p, problem, "{bad}"),
            other => panic!("{bad}: {other:?}"),
        }
    }
    // The message keeps the words the notes have always shown.
    assert_eq!(PlotError::NothingToPlot { chart: "c".into() }.to_string(), "nothing to plot: no finite points");
    assert_eq!(PlotError::Panel { panel: 2, problem: PanelProblem::UnclosedTag }.to_string(), "panel 2: an unclosed <svg> tag");
    // plotters' error is wrapped as the source.
    let e = PlotError::Drawing { chart: "c".into(), source: Box::new(std::io::Error::other("disk")) };
    assert_eq!(std::error::Error::source(&e).map(|s| s.to_string()).as_deref(), Some("disk"));
}

#[test]
fn a_tick_at_minus_zero_reads_zero() {
    // Written by hand: plotters prints 1 decimal at least, up to 5.
    for (v, want) in [(-0.0, "0.0"), (-1e-17, "0.0"), (-4e-6, "0.0"), (0.0, "0.0"), (1e-17, "0.0"), (-0.5, "-0.5"), (-2.0, "-2.0"), (0.25, "0.25"), (-1e-3, "-0.001"), (-10.0, "-10.0")] {
        assert_eq!(format_linear_tick(v), want, "{v:e}");
    }
    // The Signorini–Dirichlet bar's λ over [0, 3] (the shape of
    // data/reference/scenes/bar-dirichlet/lambda.svg): −2/3 while in contact,
    // 0 elsewhere; plotters' tick 0 of that axis was "-0.0". Each label is
    // a line of its own in the SVG.
    let labels = |svg: &str| -> Vec<String> { svg.lines().map(|l| l.trim().to_string()).filter(|l| !l.is_empty() && l.chars().all(|c| c == '-' || c == '.' || c.is_ascii_digit())).collect() };
    let lam = Series { label: "λ".into(), points: vec![(0.0, 0.0), (1.0, 0.0), (1.01, -2.0 / 3.0), (3.0, -2.0 / 3.0)], reference: false, style: Style::default() };
    let c = Chart { title: "λ(t)", x_label: "t", y_label: "λ", scale: Scale::Linear, size: (900, 450) };
    let got = labels(&line_chart(&c, std::slice::from_ref(&lam)).unwrap());
    assert!(got.contains(&"0.0".to_string()) && got.contains(&"-0.1".to_string()) && !got.contains(&"-0.0".to_string()), "{got:?}");
    let got = labels(&scatter(&c, &[lam], 1).unwrap());
    assert!(got.contains(&"0.0".to_string()) && !got.contains(&"-0.0".to_string()), "{got:?}");
}

#[test]
fn scatter_draws_one_dot_per_finite_point() {
    let pts = vec![(1.6, 0.1), (1.7, -0.2), (1.8, f64::NAN), (1.9, 0.05)];
    let c = Chart { title: "bifurcation", x_label: "ω", y_label: "x", scale: Scale::Linear, size: (640, 400) };
    let one = scatter(&c, &[Series { label: "x".into(), points: pts.clone(), reference: false, style: Style::default() }], 1).unwrap();
    assert_eq!(one.matches("<circle").count(), 3, "three finite points, three dots");
    let two = vec![
        Series { label: "stop 0".into(), points: pts.clone(), reference: false, style: Style::default() },
        Series { label: "stop 1".into(), points: vec![(0.0, 0.0)], reference: false, style: Style::default() },
    ];
    let svg = scatter(&c, &two, 2).unwrap();
    assert!(svg.contains("stop 1"), "a legend with several series");
    assert!(scatter(&c, &[Series { label: "x".into(), points: vec![(f64::NAN, 0.0)], reference: false, style: Style::default() }], 1).is_err());
}
