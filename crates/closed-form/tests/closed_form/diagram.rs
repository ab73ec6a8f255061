//! The diagram picture and the point description: the SVG's structure, that every camera is
//! labelled once at a point that really lies in it, and that the description of a point in each
//! camera agrees with Table 1 of the seed (order of the roots, oscillation segments symbolically
//! and numerically, which radicals keep their sign).

use rsts_closed_form::diagram::{
    default_window, describe_point, diagram_svg, DiagramOptions, PointDescription,
};
use rsts_closed_form::{Camera, ClosedFormError, IntegralConstants, SigmaCurve};

const A: f64 = 1.0;
const B: f64 = 0.5;

/// One point (m, h) per camera for a = 1, b = 1/2 (as in tests/closed_form/common.rs).
const CAMERA_POINTS: [(&str, f64, f64); 9] = [
    ("I+", 0.3, -0.375),
    ("I-", -1.9244, 0.4503),
    ("II+", 0.05, 1.058),
    ("II-", -0.5573, 1.463),
    ("III", -2.9877, 1.2605),
    ("IV+", 0.05, 2.0706),
    ("IV-", -0.3295, 1.7668),
    ("V", -0.7092, 1.5643),
    ("VI", -2.9877, 3.2858),
];

fn svg() -> String {
    diagram_svg(A, B, &DiagramOptions::default()).expect("diagram for a = 1, b = 0.5")
}

/// The value of attribute `name` in the tag starting at `tag`.
fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(tag[start..end].to_string())
}

/// Check that every element is closed in order (a small XML tag-stack check: no comments,
/// processing instructions or CDATA are expected in our SVG). Returns the number of elements.
fn check_nesting(svg: &str) -> usize {
    let mut stack: Vec<String> = Vec::new();
    let mut count = 0;
    let mut rest = svg;
    while let Some(i) = rest.find('<') {
        let end = rest[i..].find('>').expect("unterminated tag") + i;
        let tag = &rest[i + 1..end];
        assert!(!tag.starts_with('!') && !tag.starts_with('?'), "<{tag}>");
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(
                stack.pop().as_deref(),
                Some(name.trim()),
                "closing </{name}>"
            );
        } else {
            count += 1;
            let name: String = tag
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != '/')
                .collect();
            assert!(!name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric()));
            if !tag.ends_with('/') {
                stack.push(name);
            }
        }
        // Text between tags has no stray '>' and only escaped '&'.
        let next = rest[end + 1..]
            .find('<')
            .map_or(rest.len(), |k| k + end + 1);
        let text = &rest[end + 1..next];
        assert!(!text.contains('>'), "stray '>' in {text:?}");
        for (k, _) in text.match_indices('&') {
            let ent = &text[k..];
            assert!(
                ["&amp;", "&lt;", "&gt;", "&quot;"]
                    .iter()
                    .any(|e| ent.starts_with(e)),
                "unescaped & in {text:?}"
            );
        }
        rest = &rest[end + 1..];
    }
    assert!(stack.is_empty(), "unclosed {stack:?}");
    count
}

/// All (opening tag, text) of `<text class="camera-label" …>TEXT</text>`.
fn camera_labels(svg: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text class=\"camera-label\"") {
        let after = &rest[i..];
        let close = after.find('>').unwrap();
        let end = after.find("</text>").unwrap();
        out.push((
            after[..close].to_string(),
            after[close + 1..end].to_string(),
        ));
        rest = &after[end..];
    }
    out
}

#[test]
fn svg_is_well_formed() {
    let s = svg();
    assert!(s.starts_with("<svg "), "starts with <svg");
    assert!(s.trim_end().ends_with("</svg>"), "ends with </svg>");
    assert_eq!(s.matches("<svg").count(), 1);
    assert_eq!(s.matches("</svg>").count(), 1);
    for (open, close) in [
        ("<g ", "</g>"),
        ("<text", "</text>"),
        ("<path", "<"),
        ("<clipPath", "</clipPath>"),
        ("<defs>", "</defs>"),
        ("<title>", "</title>"),
    ] {
        if close == "<" {
            continue;
        }
        let opened = s.matches(open).count();
        // "<g>" without attributes too.
        let opened = if open == "<g " {
            opened + s.matches("<g>").count()
        } else {
            opened
        };
        assert_eq!(
            opened,
            s.matches(close).count(),
            "balanced {open} … {close}"
        );
    }
    // Every tag is closed before the next one opens, and quotes are balanced inside tags.
    let mut depth = 0i32;
    for c in s.chars() {
        match c {
            '<' => {
                depth += 1;
                assert_eq!(depth, 1, "nested '<'");
            }
            '>' => {
                depth -= 1;
                assert_eq!(depth, 0, "stray '>'");
            }
            _ => {}
        }
    }
    for tag in s.split('<').skip(1) {
        let inside = tag.split('>').next().unwrap();
        assert_eq!(inside.matches('"').count() % 2, 0, "quotes in <{inside}>");
    }
    assert!(check_nesting(&s) > 50);
    // The checker itself rejects broken markup.
    for bad in [
        "<svg><g></svg>",
        "<svg>a > b</svg>",
        "<svg>a & b</svg>",
        "<svg><g>",
    ] {
        assert!(
            std::panic::catch_unwind(|| check_nesting(bad)).is_err(),
            "{bad}"
        );
    }
    assert!(s.len() < 1_000_000, "file size {} bytes", s.len());
    assert!(s.contains("Admissible region and cameras, a = 1, b = 0.5"));
    assert!(
        s.contains(">m</text>") && s.contains(">h</text>"),
        "axis labels"
    );
}

#[test]
fn svg_labels_every_camera_once_inside_it() {
    let s = svg();
    let labels = camera_labels(&s);
    assert_eq!(labels.len(), 9, "nine camera labels: {labels:?}");
    for camera in Camera::ALL {
        let hits: Vec<&(String, String)> =
            labels.iter().filter(|(_, t)| t == camera.label()).collect();
        assert_eq!(hits.len(), 1, "label {} exactly once", camera.label());
        assert_eq!(
            s.matches(&format!(">{}</text>", camera.label())).count(),
            1,
            "{} appears once as a whole text",
            camera.label()
        );
        // The label's anchor lies in its camera.
        let tag = &hits[0].0;
        let m: f64 = attr(tag, "data-m").unwrap().parse().unwrap();
        let h: f64 = attr(tag, "data-h").unwrap().parse().unwrap();
        let d = describe_point(A, B, m, h).unwrap();
        assert_eq!(d.camera, camera, "label anchor ({m}, {h})");
        // The camera has a filled region, and its label is followed by its number of tori.
        assert!(s.contains(&format!("data-camera=\"{}\"", camera.label())));
        let after = &s[s.find(tag.as_str()).unwrap()..];
        let tori = if d.tori == 1 {
            "1 torus".to_string()
        } else {
            format!("{} tori", d.tori)
        };
        let next_text = after.split("<text").nth(2).unwrap();
        assert!(
            next_text.contains(&format!(">{tori}</text>")),
            "{tori} after {}",
            camera.label()
        );
    }
}

#[test]
fn svg_draws_every_curve_of_sigma() {
    let s = svg();
    for c in SigmaCurve::ALL {
        let id = format!("id=\"sigma-{c:?}\"");
        assert_eq!(s.matches(&id).count(), 1, "{c:?} drawn once");
        let start = s.find(&id).unwrap();
        let tag = &s[s[..start].rfind('<').unwrap()..];
        let tag = &tag[..tag.find('>').unwrap()];
        let class = attr(tag, "class").unwrap();
        let outer = matches!(
            c,
            SigmaCurve::OuterA | SigmaCurve::OuterB | SigmaCurve::Hyperbola
        );
        assert_eq!(class, if outer { "sigma outer" } else { "sigma inner" });
        let w: f64 = attr(tag, "stroke-width").unwrap().parse().unwrap();
        assert!(if outer { w > 2.0 } else { w < 2.0 }, "{c:?} width {w}");
        let d = attr(tag, "d").unwrap();
        assert!(d.starts_with('M') && d.contains('L'), "{c:?} path {d}");
    }
    // The hyperbola is a curve: many points.
    let start = s.find("id=\"sigma-Hyperbola\"").unwrap();
    let tag = &s[s[..start].rfind('<').unwrap()..];
    let d = attr(&tag[..tag.find('>').unwrap()], "d").unwrap();
    assert!(d.matches('L').count() > 100);
}

/// The main plot's map from px to (m, h), from its frame's data-window.
struct PlotMap {
    window: [f64; 4],
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

impl PlotMap {
    fn of(svg: &str) -> Self {
        let i = svg.find("<rect class=\"frame\"").unwrap();
        let tag = &svg[i..i + svg[i..].find('>').unwrap()];
        let window: Vec<f64> = attr(tag, "data-window")
            .unwrap()
            .split(' ')
            .map(|v| v.parse().unwrap())
            .collect();
        let num = |n: &str| -> f64 { attr(tag, n).unwrap().parse().unwrap() };
        Self {
            window: [window[0], window[1], window[2], window[3]],
            x: num("x"),
            y: num("y"),
            w: num("width"),
            h: num("height"),
        }
    }
    fn mh(&self, px: f64, py: f64) -> (f64, f64) {
        let [m0, m1, h0, h1] = self.window;
        (
            m0 + (px - self.x) / self.w * (m1 - m0),
            h1 - (py - self.y) / self.h * (h1 - h0),
        )
    }
}

/// Polygons in px.
type Polygons = Vec<Vec<(f64, f64)>>;

/// The polygons of a path's d ("Mx,yLx,y…Z…").
fn polygons(d: &str) -> Polygons {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    for sub in d.split('M').filter(|t| !t.is_empty()) {
        let pts = sub
            .trim_end_matches('Z')
            .split('L')
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        out.push(pts);
    }
    out
}

/// Even-odd rule over all polygons of a path.
fn inside(polys: &[Vec<(f64, f64)>], (x, y): (f64, f64)) -> bool {
    let mut c = false;
    for poly in polys {
        for k in 0..poly.len() {
            let (xi, yi) = poly[k];
            let (xj, yj) = poly[(k + poly.len() - 1) % poly.len()];
            if (yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi {
                c = !c;
            }
        }
    }
    c
}

#[test]
fn sigma_paths_lie_on_sigma() {
    let s = svg();
    let map = PlotMap::of(&s);
    for c in SigmaCurve::ALL {
        let id = format!("id=\"sigma-{c:?}\"");
        let start = s.find(&id).unwrap();
        let tag = &s[s[..start].rfind('<').unwrap()..];
        let d = attr(&tag[..tag.find('>').unwrap()], "d").unwrap();
        for poly in polygons(&d) {
            for (x, y) in poly {
                let (m, h) = map.mh(x, y);
                let r = |m: f64, h: f64| IntegralConstants::unchecked(A, B, m, h).sigma_residual(c);
                // The residual's change under the coordinates' rounding (0.005 px).
                let dm = 0.006 * (map.window[1] - map.window[0]) / map.w;
                let dh = 0.006 * (map.window[3] - map.window[2]) / map.h;
                let r0 = r(m, h);
                let tol = (r(m + dm, h) - r0).abs() + (r(m, h + dh) - r0).abs() + 1e-12;
                let k = IntegralConstants::unchecked(A, B, m, h);
                assert!(k.sigma_residual(c).abs() < tol, "{c:?} at ({m}, {h})");
            }
        }
    }
}

#[test]
fn camera_fills_match_the_classification() {
    let s = svg();
    let map = PlotMap::of(&s);
    let fills: Vec<(String, Polygons)> = s
        .match_indices("<path class=\"camera\"")
        .map(|(i, _)| {
            let tag = &s[i..i + s[i..].find('>').unwrap()];
            (
                attr(tag, "data-camera").unwrap(),
                polygons(&attr(tag, "d").unwrap()),
            )
        })
        .collect();
    assert_eq!(fills.len(), 9);
    let camera_of = |x: f64, y: f64| -> Option<String> {
        let (m, h) = map.mh(x, y);
        describe_point(A, B, m, h)
            .ok()
            .map(|d| d.camera.label().to_string())
    };
    let (mut checked, mut outside) = (0, 0);
    for j in 0..40 {
        for i in 0..50 {
            let x = map.x + (i as f64 + 0.5) * map.w / 50.0;
            let y = map.y + (j as f64 + 0.5) * map.h / 40.0;
            let here = camera_of(x, y);
            // Skip points within 2 px of a boundary.
            let near = [(2.0, 0.0), (-2.0, 0.0), (0.0, 2.0), (0.0, -2.0)]
                .iter()
                .any(|(dx, dy)| camera_of(x + dx, y + dy) != here);
            if near {
                continue;
            }
            let filled: Vec<&str> = fills
                .iter()
                .filter(|(_, polys)| inside(polys, (x, y)))
                .map(|(c, _)| c.as_str())
                .collect();
            match &here {
                Some(c) => {
                    assert_eq!(filled, [c.as_str()], "fill at px ({x}, {y})");
                    checked += 1;
                }
                None => {
                    assert!(filled.is_empty(), "inadmissible px ({x}, {y}) filled");
                    outside += 1;
                }
            }
        }
    }
    assert!(
        checked > 1000 && outside > 300,
        "{checked} inside, {outside} outside"
    );
}

#[test]
fn default_window_contains_the_camera_points() {
    let ((m0, m1), (h0, h1)) = default_window(A, B).unwrap();
    for (label, m, h) in CAMERA_POINTS {
        assert!(
            m0 < m && m < m1 && h0 < h && h < h1,
            "{label} ({m}, {h}) in window"
        );
    }
}

#[test]
fn another_field_ratio_and_custom_window() {
    // b close to a: camera V is a sliver a few px tall; b small: VI is one. Both are labelled in
    // a zoomed inset, still exactly once, at a point inside them.
    for (a, b) in [(2.0, 0.3), (1.0, 0.8), (1.0, 0.1)] {
        let s = diagram_svg(a, b, &DiagramOptions::default()).unwrap();
        let labels = camera_labels(&s);
        let mut texts: Vec<&str> = labels.iter().map(|(_, t)| t.as_str()).collect();
        texts.sort();
        assert_eq!(
            texts,
            ["I+", "I-", "II+", "II-", "III", "IV+", "IV-", "V", "VI"],
            "a = {a}, b = {b}"
        );
        for (tag, text) in &labels {
            let m: f64 = attr(tag, "data-m").unwrap().parse().unwrap();
            let h: f64 = attr(tag, "data-h").unwrap().parse().unwrap();
            let d = describe_point(a, b, m, h).unwrap();
            assert_eq!(d.camera.label(), text, "a = {a}, b = {b}: ({m}, {h})");
        }
        assert!(s.contains("class=\"inset\""), "inset for a = {a}, b = {b}");
        check_nesting(&s);
        assert_eq!(s.matches("<g ").count(), s.matches("</g>").count());
    }
    // a = 1, b = 1/2: every camera has room in the main plot.
    assert!(!svg().contains("class=\"inset\""));
    // A window with m > 0 only: cameras I+, II+, IV+ and nothing else.
    let opts = DiagramOptions {
        m_range: Some((0.05, 3.0)),
        h_range: Some((-2.0, 5.0)),
        ..DiagramOptions::default()
    };
    let s = diagram_svg(A, B, &opts).unwrap();
    let mut texts: Vec<String> = camera_labels(&s).into_iter().map(|(_, t)| t).collect();
    texts.sort();
    assert_eq!(texts, ["I+", "II+", "IV+"]);
}

#[test]
fn bad_parameters_are_errors() {
    for (a, b) in [
        (0.5, 1.0),
        (1.0, 1.0),
        (1.0, 0.0),
        (1.0, -0.5),
        (f64::NAN, 0.5),
    ] {
        let e = diagram_svg(a, b, &DiagramOptions::default()).unwrap_err();
        assert!(matches!(e, ClosedFormError::Parameters(_)), "{e}");
        assert!(
            e.to_string().contains("a > b > 0") || e.to_string().contains("finite"),
            "{e}"
        );
        assert!(describe_point(a, b, 0.3, -0.375).is_err());
    }
    let bad = DiagramOptions {
        m_range: Some((1.0, -1.0)),
        ..DiagramOptions::default()
    };
    let e = diagram_svg(A, B, &bad).unwrap_err();
    assert!(e.to_string().contains("m_range"), "{e}");
    let bad = DiagramOptions {
        h_range: Some((0.0, f64::INFINITY)),
        ..DiagramOptions::default()
    };
    assert!(diagram_svg(A, B, &bad).is_err());
    let bad = DiagramOptions {
        width: 10,
        ..DiagramOptions::default()
    };
    assert!(diagram_svg(A, B, &bad).is_err());
}

fn close(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-12 * (1.0 + y.abs())
}

/// The numeric value Table 1's symbol stands for.
fn symbol_value(sym: &str, d: &PointDescription) -> f64 {
    match sym {
        "a" => d.a,
        "-a" => -d.a,
        "b" => d.b,
        "-b" => -d.b,
        "θ1" => d.theta1,
        "θ2" => d.theta2,
        other => panic!("unknown symbol {other}"),
    }
}

/// "[A, B]" or "[A (±∞) B]" → (A, B, through infinity).
fn parse_segment(s: &str) -> (String, String, bool) {
    let inner = s.trim_start_matches('[').trim_end_matches(']');
    if let Some((l, r)) = inner.split_once(" (±∞) ") {
        (l.to_string(), r.to_string(), true)
    } else {
        let (l, r) = inner.split_once(", ").unwrap();
        (l.to_string(), r.to_string(), false)
    }
}

#[test]
fn a_point_in_each_camera_agrees_with_table1() {
    for (label, m, h) in CAMERA_POINTS {
        let d = describe_point(A, B, m, h).unwrap();
        assert_eq!(d.camera.label(), label, "camera of ({m}, {h})");
        assert_eq!(d.table1_roots, d.camera.table1_roots());
        let expected_tori = match d.camera {
            Camera::IPlus | Camera::IMinus => 1,
            Camera::IIPlus | Camera::IIMinus | Camera::III => 2,
            _ => 4,
        };
        assert_eq!(d.tori, expected_tori, "tori in {label}");
        // θ's from their definitions.
        let ell = (2.0 * 1.25 * m * m + 2.0 * h * m + 1.0).sqrt();
        assert!(close(d.ell, ell));
        assert!((d.theta1 - (ell - 1.0) / (2.0 * m)).abs() < 1e-12);
        assert!((d.theta2 - (ell + 1.0) / (2.0 * m)).abs() < 1e-12);
        // The order of the roots of Φ printed in Table 1 holds numerically.
        let chain: Vec<&str> = d.table1_roots.split(" < ").collect();
        for w in chain.windows(2) {
            let (x, y) = (symbol_value(w[0], &d), symbol_value(w[1], &d));
            assert!(x < y, "{label}: {} = {x} < {} = {y}", w[0], w[1]);
        }
        // Segments: symbolic form as in Table 1, numeric ends equal to the symbols' values.
        let (t1_s1, t1_s2) = d.camera.table1_segments();
        for (v, table) in [(&d.s1, t1_s1), (&d.s2, t1_s2)] {
            assert_eq!(v.table1, table, "{label} {}", v.variable);
            let (l, r, inf) = parse_segment(table);
            assert_eq!(v.through_infinity, inf, "{label} {}", v.variable);
            assert!(
                close(v.start.value, symbol_value(&l, &d)),
                "{label} {} start",
                v.variable
            );
            assert!(
                close(v.end.value, symbol_value(&r, &d)),
                "{label} {} end",
                v.variable
            );
            if inf {
                // Table 1: [A (±∞) B] means B < 0 < A and 1/s1 on [1/B, 1/A].
                assert!(v.end.value < 0.0 && v.start.value > 0.0);
            } else {
                assert!(v.start.value < v.end.value);
            }
            if v.variable == "s1" {
                let [x0, x1] = v.coordinate_segment;
                assert!(close(x0, 1.0 / v.end.value) && close(x1, 1.0 / v.start.value));
            } else {
                assert_eq!(v.coordinate_segment, [v.start.value, v.end.value]);
            }
            assert!(v.k2 >= 0.0 && v.k2 < 1.0 && close(v.k2 + v.kc2, 1.0));
            assert!(v.period > 0.0 && close(v.period * v.frequency, 2.0 * std::f64::consts::PI));
        }
        assert!(close(d.rotation_number, d.s1.frequency / d.s2.frequency));
        // The normal type: λ² = −4r⁴mℓ², hyperbolic exactly in the cameras with m < 0.
        let r4 = (1.0f64 - 0.25).powi(2);
        assert!(
            close(d.normal.lambda2, -4.0 * r4 * d.m * d.ell * d.ell),
            "{label}"
        );
        let hyperbolic = d.normal.kind == rsts_closed_form::manifold::NormalType::Hyperbolic;
        assert_eq!(
            hyperbolic,
            label.ends_with('-') || ["III", "V", "VI"].contains(&label),
            "{label}"
        );
        assert!(d
            .to_string()
            .contains(&format!("N is normally {}", d.normal.kind)));
        // Seed sec. 3 (after Table 2): F1* keeps its sign in III, V, VI; F2 in II, IV, V;
        // G1* in IV; G2 in VI; all other radicals change sign.
        let numeral = label.trim_end_matches(['+', '-']);
        let constant = |name: &str| -> bool {
            let all = d.s1.radicals.iter().chain(d.s2.radicals.iter());
            all.filter(|r| r.name == name)
                .map(|r| r.constant_sign)
                .next()
                .unwrap()
        };
        assert_eq!(
            constant("F1*"),
            ["III", "V", "VI"].contains(&numeral),
            "{label} F1*"
        );
        assert_eq!(
            constant("F2"),
            ["II", "IV", "V"].contains(&numeral),
            "{label} F2"
        );
        assert_eq!(constant("G1*"), numeral == "IV", "{label} G1*");
        assert_eq!(constant("G2"), numeral == "VI", "{label} G2");
        // Number of tori = 2^(number of constant-sign radicals).
        let n_const =
            d.s1.radicals
                .iter()
                .chain(d.s2.radicals.iter())
                .filter(|r| r.constant_sign)
                .count();
        assert_eq!(d.tori, 1 << n_const, "{label}");
        // The text form names the camera and the segments.
        let text = d.to_string();
        assert!(text.contains(&format!("camera {label}")), "{text}");
        assert!(text.contains(t1_s1) && text.contains(t1_s2), "{text}");
        // JSON.
        let json = serde_json::to_value(&d).unwrap();
        assert_eq!(json["camera"], label);
        assert_eq!(json["s1"]["table1"], t1_s1);
        assert_eq!(json["tori"], expected_tori);
    }
}

#[test]
fn i_plus_segment_of_s1_is_a_to_theta2() {
    let d = describe_point(A, B, 0.3, -0.375).unwrap();
    assert_eq!(d.s1.start.value, 1.0);
    assert!(close(d.s1.end.value, d.theta2));
    assert!(d.theta2 > 1.0);
    assert_eq!(d.s2.start.value, -0.5);
    assert!(close(d.s2.end.value, d.theta1));
    let json = serde_json::to_value(&d).unwrap();
    assert_eq!(json["s1"]["start"]["label"], "a");
    assert_eq!(json["s1"]["end"]["label"], "theta2");
}

#[test]
fn m_zero_has_theta2_at_infinity() {
    // m = 0: θ2 = ∞, s1 ∈ [a, +∞) (x = 1/s1 ∈ [0, 1/a]), camera I+ for h below 2b.
    let d = describe_point(A, B, 0.0, -0.5).unwrap();
    assert_eq!(d.camera, Camera::IPlus);
    assert!(d.theta2.is_infinite());
    assert!(close(d.theta1, -0.25), "θ1 = h/2 at m = 0");
    assert_eq!(d.s1.end.value, f64::INFINITY);
    assert_eq!(d.s1.start.value, 1.0);
    let json = serde_json::to_value(&d).unwrap();
    assert!(json["theta2"].is_null());
    assert!(json["s1"]["end"]["value"].is_null());
    assert!(d.to_string().contains("+∞"));
}

#[test]
fn inadmissible_points_and_points_on_sigma_are_errors_naming_the_curve() {
    // Below both boundary lines.
    let e = describe_point(A, B, 0.3, -1.5).unwrap_err();
    assert!(matches!(e, ClosedFormError::NotAdmissible(_)), "{e}");
    assert!(
        e.to_string().contains("h = r²m − 2a") || e.to_string().contains("h = −r²m − 2b"),
        "{e}"
    );
    // Beyond the hyperbola.
    let e = describe_point(A, B, -1.0, 5.0).unwrap_err();
    assert!(matches!(e, ClosedFormError::NotAdmissible(_)), "{e}");
    assert!(e.to_string().contains("hyperbola"), "{e}");
    // On each curve of Σ (exact in binary for a = 1, b = 1/2).
    for (curve, m, h) in [
        (SigmaCurve::OuterA, 1.0, -1.25),
        (SigmaCurve::OuterB, -1.0, -0.25),
        (SigmaCurve::Hyperbola, -2.0, 2.75),
        (SigmaCurve::InnerA, 0.5, 2.375),
        (SigmaCurve::InnerB, -0.5, 1.375),
    ] {
        let e = describe_point(A, B, m, h).unwrap_err();
        assert!(matches!(e, ClosedFormError::OnSigma(_)), "{curve:?}: {e}");
        assert!(e.to_string().contains(curve.equation()), "{curve:?}: {e}");
    }
    assert!(describe_point(A, B, f64::NAN, 0.0).is_err());
}

/// Writes example pictures and descriptions to look at:
/// `cargo test -p rsts-closed-form --release --test closed_form diagram:: -- --ignored --nocapture`.
#[test]
#[ignore]
fn write_example_pictures() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("diagram");
    std::fs::create_dir_all(&dir).unwrap();
    for (a, b) in [(1.0, 0.5), (2.0, 0.3), (1.0, 0.8), (1.0, 0.1)] {
        let path = dir.join(format!("diagram-a{a}-b{b}.svg"));
        std::fs::write(
            &path,
            diagram_svg(a, b, &DiagramOptions::default()).unwrap(),
        )
        .unwrap();
        println!("{}", path.display());
    }
    let zoom = DiagramOptions {
        m_range: Some((-1.2, -0.2)),
        h_range: Some((1.2, 2.0)),
        ..DiagramOptions::default()
    };
    let path = dir.join("diagram-a1-b0.5-zoom.svg");
    std::fs::write(&path, diagram_svg(A, B, &zoom).unwrap()).unwrap();
    println!("{}", path.display());
    let small = DiagramOptions {
        width: 700,
        height: 540,
        ..DiagramOptions::default()
    };
    for (a, b) in [(1.0, 0.5), (1.0, 0.8)] {
        let path = dir.join(format!("diagram-a{a}-b{b}-small.svg"));
        std::fs::write(&path, diagram_svg(a, b, &small).unwrap()).unwrap();
        println!("{}", path.display());
    }
    for (_, m, h) in CAMERA_POINTS {
        println!("{}", describe_point(A, B, m, h).unwrap());
    }
    println!("{}", describe_point(A, B, 0.0, -0.5).unwrap());
    println!(
        "{}",
        serde_json::to_string_pretty(&describe_point(A, B, -0.7092, 1.5643).unwrap()).unwrap()
    );
}

#[test]
fn odd_windows_and_sizes_give_well_formed_pictures() {
    for (m_range, h_range, width, height) in [
        // Entirely outside the admissible region.
        ((-3.0, -2.0), (-5.0, -4.0), 1000, 720),
        // A tiny window inside camera I+.
        ((0.3, 0.3 + 1e-9), (-0.375, -0.375 + 1e-9), 1000, 720),
        // Huge.
        ((-1e4, 1e4), (-1e4, 1e4), 1000, 720),
        // Around the tangency of the hyperbola with h = r²m + 2a at m = −1/(2a).
        ((-0.6, -0.4), (1.4, 1.8), 700, 540),
        ((-3.0, 2.3), (-2.0, 4.4), 3000, 2000),
    ] {
        let opts = DiagramOptions {
            m_range: Some(m_range),
            h_range: Some(h_range),
            width,
            height,
            title: Some("a <test> & title".to_string()),
        };
        let s = diagram_svg(A, B, &opts).unwrap();
        assert!(s.starts_with("<svg ") && s.trim_end().ends_with("</svg>"));
        assert_eq!(s.matches("<g ").count(), s.matches("</g>").count());
        assert_eq!(s.matches("<text").count(), s.matches("</text>").count());
        check_nesting(&s);
        assert!(s.contains("a &lt;test&gt; &amp; title"));
        assert!(
            !s.contains("NaN") && !s.contains("inf"),
            "{m_range:?} {h_range:?}"
        );
        let labels = camera_labels(&s);
        for (tag, text) in &labels {
            let m: f64 = attr(tag, "data-m").unwrap().parse().unwrap();
            let h: f64 = attr(tag, "data-h").unwrap().parse().unwrap();
            assert_eq!(describe_point(A, B, m, h).unwrap().camera.label(), text);
        }
        let mut texts: Vec<&str> = labels.iter().map(|(_, t)| t.as_str()).collect();
        texts.sort();
        texts.dedup();
        assert_eq!(texts.len(), labels.len(), "each camera once: {texts:?}");
        if m_range.0 == 0.3 {
            assert_eq!(texts, ["I+"]);
        }
        if m_range.0 == -3.0 && width == 1000 {
            assert!(texts.is_empty());
        }
    }
}

#[test]
#[ignore]
fn timing() {
    for (w, h) in [(1000, 720), (2000, 1440)] {
        let t = std::time::Instant::now();
        let opts = DiagramOptions {
            width: w,
            height: h,
            ..DiagramOptions::default()
        };
        let s = diagram_svg(A, B, &opts).unwrap();
        println!("{w}x{h}: {:?}, {} bytes", t.elapsed(), s.len());
    }
    let t = std::time::Instant::now();
    for i in 0..10000 {
        let _ = describe_point(A, B, 0.3, -0.375 + 1e-6 * i as f64);
    }
    println!("describe: {:?} per point", t.elapsed() / 10000);
}
