//! Scan the (m, h) window: the semi-moving kind and the symmetry-relevant sign changes per camera.
use rsts_closed_form::diagram::default_window;
use rsts_closed_form::{ExplicitMotion, TorusChoice};
use rsts_geometry::classify::motion_kinds;
use std::collections::BTreeMap;
fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let (a, b) = (
        args.first().copied().unwrap_or(1.0),
        args.get(1).copied().unwrap_or(0.5),
    );
    let ((m0, m1), (h0, h1)) = default_window(a, b).unwrap();
    let n = 60;
    let mut count: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for i in 0..n {
        for j in 0..n {
            let m = m0 + (m1 - m0) * (i as f64 + 0.5) / n as f64;
            let h = h0 + (h1 - h0) * (j as f64 + 0.5) / n as f64;
            let Ok(mo) = ExplicitMotion::<f64>::new(a, b, m, h, TorusChoice::default()) else {
                continue;
            };
            let k = motion_kinds(&mo);
            let key = format!(
                "semi {} first {} second {}",
                k.semi_moving.as_str(),
                k.first_partial.as_str(),
                k.second_partial.as_str()
            );
            *count
                .entry(mo.camera.label().to_string())
                .or_default()
                .entry(key)
                .or_default() += 1;
        }
    }
    for (c, v) in count {
        println!("{c}: {v:?}");
    }
}
