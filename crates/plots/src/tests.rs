use super::*;
use crate::labels::{overlap, Rect};

fn chart(series: Vec<Series>, x: Scale, y: Scale) -> Chart {
    Chart {
        title: "t <1>".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        x_scale: x,
        y_scale: y,
        series,
        ..Chart::default()
    }
}

/// The values of an attribute over the elements that carry `marker`.
fn attrs(svg: &str, marker: &str, key: &str) -> Vec<String> {
    svg.lines()
        .filter(|l| l.contains(marker))
        .filter_map(|l| {
            let rest = l.split(&format!(r#" {key}=""#)).nth(1)?;
            Some(rest.split('"').next()?.to_string())
        })
        .collect()
}

fn num(svg: &str, marker: &str, key: &str) -> Vec<f64> {
    attrs(svg, marker, key)
        .iter()
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
fn log_axes_are_labelled_every_decade_and_points_land_inside_the_frame() {
    let c = chart(
        vec![Series::new(
            "a&b",
            vec![(1e-12, 1e-4), (1e-6, 1e-2), (1e-3, 1.0)],
            Style::LineMarkers,
        )],
        Scale::Log10,
        Scale::Log10,
    );
    let svg = render_svg(&c).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let x: Vec<String> = attrs(&svg, r#"class="tick x""#, "data-v");
    let want: Vec<String> = (-12..=-3).map(|k| format!("1e{k}")).collect();
    assert_eq!(x, want, "a label at every decade of the x axis");
    let y = attrs(&svg, r#"class="tick y""#, "data-v");
    assert_eq!(y, ["1e-4", "1e-3", "1e-2", "1e-1", "1e0"]);
    assert!(svg.contains(r#"10<tspan dy="-5" font-size="9">−6</tspan>"#));
    assert!(
        svg.contains("a&amp;b") && svg.contains("t &lt;1&gt;"),
        "text is escaped"
    );
    let (fx, fw) = (
        num(&svg, r##"fill="none" stroke="#444""##, "x")[0],
        num(&svg, r##"fill="none" stroke="#444""##, "width")[0],
    );
    let cx = num(&svg, "<circle", "cx");
    assert_eq!(cx.len(), 3);
    assert!(cx.iter().all(|x| *x > fx && *x < fx + fw), "{cx:?}");
}

#[test]
fn the_legend_is_right_of_the_frame_and_point_labels_do_not_collide() {
    // Two series with points close together, each point labelled with its tolerance.
    let tolerances = ["1e-6", "1e-8", "1e-10", "1e-12"];
    let mk = |name: &str, shift: f64| {
        Series::new(
            name,
            (0..4)
                .map(|k| {
                    (
                        10f64.powi(-6 - 2 * k) * shift,
                        1e-3 * (k + 1) as f64 * shift,
                    )
                })
                .collect(),
            Style::LineMarkers,
        )
        .with_point_labels(tolerances.iter().map(|t| t.to_string()).collect())
    };
    let c = chart(
        vec![mk("dop853", 1.0), mk("a much longer name", 1.15)],
        Scale::Log10,
        Scale::Log10,
    );
    let svg = render_svg(&c).unwrap();
    let frame_right = num(&svg, r##"fill="none" stroke="#444""##, "x")[0]
        + num(&svg, r##"fill="none" stroke="#444""##, "width")[0];
    let legend_x = num(&svg, r#"<g class="legend"><rect"#, "x")[0];
    assert!(legend_x > frame_right, "{legend_x} {frame_right}");
    let legend_right = legend_x + num(&svg, r#"<g class="legend"><rect"#, "width")[0];
    assert!(legend_right <= c.width as f64, "{legend_right}");
    // Every point has its label, and no two label boxes overlap.
    let block = svg.split(r#"<g class="point-labels""#).nth(1).unwrap();
    let block = block.split("</g>").next().unwrap();
    let boxes: Vec<Rect> = block
        .lines()
        .filter(|l| l.starts_with("<text"))
        .map(|l| {
            let get = |k: &str| num(l, "<text", k)[0];
            let text = l.split('>').nth(1).unwrap().split('<').next().unwrap();
            let w = 5.6 * text.chars().count() as f64;
            let x0 = match attrs(l, "<text", "text-anchor")[0].as_str() {
                "start" => get("x"),
                "end" => get("x") - w,
                _ => get("x") - w / 2.0,
            };
            (x0, get("y") - 9.0, x0 + w, get("y") + 2.0)
        })
        .collect();
    assert_eq!(boxes.len(), 8);
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            assert_eq!(overlap(*a, *b), 0.0, "{a:?} {b:?}");
        }
    }
    for t in tolerances {
        assert_eq!(block.matches(&format!(">{t}<")).count(), 2, "{t}");
    }
}

/// A band is one polygon in its series' colour, its edges at the points given (the low
/// edge forward, the high edge back), inside the frame, which widens to hold it.
#[test]
fn a_band_is_shaded_between_its_edges() {
    let mut s = Series::new(
        "dop853",
        vec![(1e-8, 1e-3), (1e-10, 2e-3), (1e-12, 4e-3)],
        Style::LineMarkers,
    );
    s.band = vec![
        ((1e-9, 1e-3), (1e-7, 1e-3)),
        ((1e-11, 2e-3), (1e-9, 2e-3)),
        ((1e-13, 4e-3), (1e-11, 4e-3)),
    ];
    s.color = Some("#D55E00".into());
    let svg = render_svg(&chart(vec![s], Scale::Log10, Scale::Log10)).unwrap();
    let band: Vec<&str> = svg
        .lines()
        .filter(|l| l.contains(r#"class="band""#))
        .collect();
    assert_eq!(band.len(), 1, "{svg}");
    assert!(band[0].contains(r##"fill="#D55E00""##));
    let pts: Vec<(f64, f64)> = attrs(band[0], "<polygon", "points")[0]
        .split(' ')
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect();
    assert_eq!(pts.len(), 6);
    // Low edge forward, high edge back: x of points 0 and 5 (same y) differ by 2 decades.
    assert_eq!(pts[0].1, pts[5].1);
    assert!(pts[5].0 > pts[0].0);
    let x: Vec<String> = attrs(&svg, r#"class="tick x""#, "data-v");
    assert_eq!(
        x.first().map(String::as_str),
        Some("1e-13"),
        "the axis holds the band"
    );
    assert_eq!(x.last().map(String::as_str), Some("1e-7"));
    assert!(
        svg.find(r#"class="band""#) < svg.find(r#"class="series""#),
        "drawn under the line"
    );
}

#[test]
fn non_positive_values_are_dropped_on_log_axes_and_empty_charts_are_errors() {
    let c = chart(
        vec![Series::new(
            "s",
            vec![(0.0, 1.0), (-1.0, 2.0), (f64::NAN, 3.0)],
            Style::Markers,
        )],
        Scale::Log10,
        Scale::Linear,
    );
    assert_eq!(render_svg(&c), Err(PlotError::Empty));
    let c = chart(
        vec![Series::new(
            "s",
            vec![(0.0, 1.0), (2.0, 2.0)],
            Style::Markers,
        )],
        Scale::Log10,
        Scale::Linear,
    );
    assert_eq!(render_svg(&c).unwrap().matches("<circle").count(), 1);
    let mut small = chart(vec![], Scale::Linear, Scale::Linear);
    small.width = 10;
    assert!(render_svg(&small).is_err());
}

#[test]
fn a_second_title_line_is_a_subtitle_and_the_frame_moves_down_for_it() {
    let series = vec![Series::new("s", vec![(0.0, 1.0), (1.0, 2.0)], Style::Line)];
    let one = render_svg(&chart(series.clone(), Scale::Linear, Scale::Linear)).unwrap();
    let mut c = chart(series, Scale::Linear, Scale::Linear);
    c.title = "main <t>\nthe motion & more".into();
    let two = render_svg(&c).unwrap();
    assert!(two.contains(">main &lt;t&gt;</text>"), "{two}");
    assert_eq!(
        attrs(&two, r#"class="subtitle""#, "y"),
        ["45"],
        "one subtitle line"
    );
    assert!(two.contains(">the motion &amp; more</text>"));
    assert!(!one.contains("subtitle"));
    let frame_top = |svg: &str| num(svg, r##"fill="none" stroke="#444""##, "y")[0];
    assert!(
        frame_top(&two) > frame_top(&one) + 10.0,
        "the frame starts below the subtitle"
    );
}
