//! Antialiased text for the pictures: DejaVu Sans (a subset with ASCII, Greek and a few
//! mathematical signs, in `assets/`; Bitstream Vera licence) rasterised with ab_glyph.

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans-subset.ttf");

fn font() -> FontRef<'static> {
    FontRef::try_from_slice(FONT).expect("the embedded font parses")
}

/// Width in px of `text` at `size` px.
pub fn width(text: &str, size: f32) -> f32 {
    let f = font();
    let s = f.as_scaled(PxScale::from(size));
    let mut w = 0.0;
    let mut prev = None;
    for c in text.chars() {
        let id = s.glyph_id(c);
        if let Some(p) = prev {
            w += s.kern(p, id);
        }
        w += s.h_advance(id);
        prev = Some(id);
    }
    w
}

/// Draws `text` with its baseline starting at (x, y): `plot(px, py, coverage)` for each pixel
/// a glyph covers (coverage in 0..=1).
pub fn draw(text: &str, size: f32, x: f32, y: f32, mut plot: impl FnMut(i64, i64, f32)) {
    let f = font();
    let scale = PxScale::from(size);
    let s = f.as_scaled(scale);
    let mut caret = x;
    let mut prev = None;
    for c in text.chars() {
        let id = s.glyph_id(c);
        if let Some(p) = prev {
            caret += s.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scale, point(caret, y));
        caret += s.h_advance(id);
        prev = Some(id);
        if let Some(outline) = f.outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                plot(b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64, cov)
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_character_of_the_titles_has_a_glyph() {
        let f = font();
        for c in "P-surface (ω, body frame) Π-surface (Ω, fixed frame) camera I+ I− II III IV V VI \
                  a = 1, b = 0.5, m = −0.7092, h = 1.5643, torus 3 of 4 ψ 0123456789 ×·"
            .chars()
        {
            assert_ne!(f.glyph_id(c).0, 0, "no glyph for {c:?}");
        }
        assert!(width("camera V", 12.0) > 40.0 && width("camera V", 12.0) < 70.0);
        let mut covered = 0;
        draw("Ω", 20.0, 0.0, 20.0, |_, _, c| {
            covered += (c > 0.5) as usize
        });
        assert!(covered > 30, "{covered}");
    }
}
